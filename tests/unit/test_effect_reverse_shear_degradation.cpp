// reverse_shear_degradation: toward the mated position the strength is sigma_n tan(phi_b - w i).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "models/joint_laws/continuously_yielding.hpp"
#include "tests/unit/effect_test_util.hpp"

using namespace rockdem;
using namespace rockdem::testutil;

namespace {
constexpr double kDeg = std::numbers::pi / 180.0;
}  // namespace

TEST(EffectReverseShearDegradation, DisabledLeavesEveryLawBitForBitIdentical) {
  expect_disabled_is_bit_identical({effect("reverse_shear_degradation", {{"enabled", "false"}, {"weight", "3"}})});
}

// Mohr-Coulomb (phi = 38 deg, psi = 2.4 deg) at 3 MPa, 0 -> 10 mm -> 0: the forward plateau is
// 3 tan 38 deg, the reverse one exactly 3 tan(38 - 2.4 deg); with w = 2, 3 tan(38 - 4.8 deg).
TEST(EffectReverseShearDegradation, MohrCoulombReverseStrengthIsPattonsClosedForm) {
  for (const double w : {1.0, 2.0}) {
    auto m = model("mohr_coulomb", mc_report({{"dilation", "reversible"}}),
                   {effect("reverse_shear_degradation", {{"weight", std::to_string(w)}})});
    ElementDriver d(*m);
    const auto f = d.run({cnl(3e6, ShearPath::cycles(0.01, 1, 1e-4, true))});
    const std::size_t rev = first_reverse_row(f);
    EXPECT_NEAR(max_tau(f, 0, rev), 3.0 * std::tan(38.0 * kDeg), 1e-6);
    EXPECT_NEAR(min_tau(f, rev, f.rows.size()), -3.0 * std::tan((38.0 - w * 2.4) * kDeg), 1e-6) << w;
    // and the stress sits on that plateau for most of the return stroke
    const std::size_t mid = row_at(f, 5.0, rev);
    ASSERT_LT(mid, f.rows.size());
    EXPECT_NEAR(f.rows[mid].shear_stress_MPa, -3.0 * std::tan((38.0 - w * 2.4) * kDeg), 1e-6);
  }
  // Without the effect the reverse plateau is the forward one (the report's complaint).
  auto plain = model("mohr_coulomb", mc_report({{"dilation", "reversible"}}));
  ElementDriver d(*plain);
  const auto g = d.run({cnl(3e6, ShearPath::cycles(0.01, 1, 1e-4, true))});
  EXPECT_NEAR(min_tau(g, first_reverse_row(g), g.rows.size()), -3.0 * std::tan(38.0 * kDeg), 1e-6);
}

// Continuously-Yielding: the return stroke is bounded by sigma_n tan(2 phi - phi_m) (i = phi_m -
// phi), far below the forward strength; the base law's reverse peak is close to the end of
// forward shearing instead.
TEST(EffectReverseShearDegradation, ContinuouslyYieldingReverseBoundUsesPhiMinusRoughness) {
  const auto params = cy_report({{"dilation", "reversible"}});
  auto m = model("continuously_yielding", params, {effect("reverse_shear_degradation")});
  ElementDriver d(*m);
  const auto f = d.run({cnl(3e6, ShearPath::cycles(0.01, 1, 1e-4, true))});
  const std::size_t rev = first_reverse_row(f);
  const double end_forward = f.rows[rev - 1].shear_stress_MPa;
  const auto s = law_state<ContinuouslyYielding::State>(d.state());
  const ContinuouslyYielding::Params p =
      bind_params<ContinuouslyYielding::Params>(params, "continuously_yielding", "test");
  const double phim = ContinuouslyYielding::phi_m(p, s.plastic_slip);
  const double bound = 3.0 * std::tan(2.0 * p.friction - phim);
  EXPECT_LT(-f.rows.back().shear_stress_MPa, bound * (1.0 + 1e-9));  // never above the bound
  EXPECT_GT(-f.rows.back().shear_stress_MPa, 0.97 * bound);          // and approaching it
  EXPECT_LT(-min_tau(f, rev, f.rows.size()), 0.85 * end_forward);
  auto plain = model("continuously_yielding", params);
  ElementDriver dp(*plain);
  const auto g = dp.run({cnl(3e6, ShearPath::cycles(0.01, 1, 1e-4, true))});
  EXPECT_GT(-min_tau(g, first_reverse_row(g), g.rows.size()), 0.9 * end_forward);
}

// Barton-Bandis: the reverse strength is sigma_n tan(phi_r - JRC_mob log10(JCS/sigma_n)); at the
// end of forward shearing (10 mm, about 7.6 delta_p) the mobilised roughness is positive, so the
// reverse stroke sits below the residual-friction line 3 tan(28.4 deg), while the plain law's
// reverse peak equals the end-of-forward strength.
TEST(EffectReverseShearDegradation, BartonBandisReverseStrengthBelowResidualFriction) {
  const auto params = bb_report({{"dilation", "reversible"}});
  auto m = model("barton_bandis", params, {effect("reverse_shear_degradation")});
  ElementDriver d(*m);
  const auto f = d.run({cnl(3e6, ShearPath::cycles(0.01, 1, 1e-4, true))});
  const std::size_t rev = first_reverse_row(f);
  EXPECT_NEAR(max_tau(f, 0, rev), 2.5948, 2e-3);  // forward peak unchanged
  const double reverse = -min_tau(f, rev, f.rows.size());
  EXPECT_LT(reverse, 3.0 * std::tan(28.4 * kDeg));
  EXPECT_GT(reverse, 0.5);
}

TEST(EffectReverseShearDegradation, DescribedInTheRegistry) {
  const auto* e = EffectRegistry::instance().find("reverse_shear_degradation");
  ASSERT_NE(e, nullptr);
  EXPECT_NE(e->reference.find("Patton"), std::string::npos);
  ASSERT_EQ(e->params.size(), 2u);
  EXPECT_EQ(e->params[1].name, "weight");
}

// A joint pre-stressed in shear (a rock mass's in-situ state: 2.2 MPa at 3 MPa, below the forward
// bound 3 tan 39.3 deg = 2.45 MPa, with no offset) that vibrates about its mated position: moving
// back toward it, the lowered bound 3 tan(2 phi - phi_m) = 1.57 MPa would lie under the stress it
// carries, and Continuously-Yielding would return to it through F < 0 (a negative tangent, about
// -1.6 ks here). The bound never drops under the stress carried in the direction of motion, so
// the tangent stays >= 0; a real reversal (stress on the other side) is unaffected (above).
TEST(EffectReverseShearDegradation, NeverDropsTheBoundUnderTheStressCarriedInTheDirectionOfMotion) {
  const auto params = cy_report({{"dilation", "reversible"}});
  for (const bool with_effect : {false, true}) {
    auto m = with_effect ? model("continuously_yielding", params, {effect("reverse_shear_degradation")})
                         : model("continuously_yielding", params);
    JointStateBlock b;
    m->init(b);
    ContinuouslyYielding::State s = law_state<ContinuouslyYielding::State>(b);
    s.sigma_n = 3e6;
    s.tau = 2.2e6;
    s.u_s = -1e-6;     // a hair on the negative side of the mated position
    s.last_dir = -1.0;  // it was moving away from it: the next increment is a reversal
    std::memcpy(b.bytes.data(), &s, sizeof s);
    JointKinematics k;
    k.du_s = 1e-7;  // back toward the mated position
    k.dt = 1e-5;
    JointResponse r;
    m->update(b, k, r);
    const double tau = law_state<ContinuouslyYielding::State>(b).tau;
    // (Within a thousandth of ks: the bound is scaled to the normal stress the increment ends at.)
    EXPECT_GE(tau, 2.2e6 - 1e-3 * 29.312e9 * 1e-7)
        << (with_effect ? "with" : "without") << " the effect: the stress fell by " << 2.2e6 - tau
        << " Pa on a shear increment in its own direction (a negative tangent; 4.7 kPa before the rule)";
    EXPECT_LE(tau, 2.2e6 + 29.312e9 * 1e-7 * (1.0 + 1e-12));  // and never stiffer than elastic
  }
}
