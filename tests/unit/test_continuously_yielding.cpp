#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "models/joint_laws/continuously_yielding.hpp"
#include "tests/unit/joint_law_test_util.hpp"

using namespace rockdem;
using namespace rockdem::testutil;

namespace {
constexpr double kDeg = std::numbers::pi / 180.0;
ContinuouslyYielding::Params bind_cy(const RawValues& v) {
  return bind_params<ContinuouslyYielding::Params>(v, "cy", "test");
}
}  // namespace

TEST(ContinuouslyYielding, StiffnessPowerLawsAreBoundedEq39) {
  const auto p = bind_cy(cy_report());  // Table 4-4, test 9
  EXPECT_NEAR(ContinuouslyYielding::normal_stiffness(p, 1e6), 29.361e9, 1.0);
  EXPECT_NEAR(ContinuouslyYielding::normal_stiffness(p, 1.5e6), 29.361e9 * std::pow(1.5, 0.6783), 10.0);
  EXPECT_NEAR(ContinuouslyYielding::normal_stiffness(p, 3e6), 46.109e9, 1.0);  // capped at maxjkn
  EXPECT_NEAR(ContinuouslyYielding::normal_stiffness(p, 0.0), 29.361e9, 1.0);  // floor at minjkn
  EXPECT_NEAR(ContinuouslyYielding::shear_stiffness(p, 3e6), 29.312e9, 1.0);   // jes = 0
  const auto q = bind_cy(cy_report({{"ks_exponent", "0.5"}, {"ks_min", "1 GPa/m"}, {"ks_max", "100 GPa/m"}}));
  EXPECT_NEAR(ContinuouslyYielding::shear_stiffness(q, 4e6), 29.312e9 * 2.0, 10.0);
}

TEST(ContinuouslyYielding, FactorFFollowsEq311FromTheVirginState) {
  auto m = model("continuously_yielding", cy_report());
  const auto p = bind_cy(cy_report());
  ElementDriver d(*m);
  const ElementStage st = cnl(3e6, ShearPath::cycles(0.01, 1, 1e-4));
  d.begin_stage(st);
  // Small increments: d tau = (1 - tau/tau_o) ks du with tau_o = sigma_n tan(phi_m).
  for (int i = 0; i < 50; ++i) {
    const auto s0 = law_state<ContinuouslyYielding::State>(d.state());
    const double tau_o = 3e6 * std::tan(ContinuouslyYielding::phi_m(p, s0.plastic_slip));
    d.step(st, 1e-7, 0.0);
    const auto s1 = law_state<ContinuouslyYielding::State>(d.state());
    const double f = 1.0 - s0.tau / tau_o;
    EXPECT_NEAR(s1.tau - s0.tau, f * 29.312e9 * 1e-7, 1e-3);
    EXPECT_NEAR(s1.plastic_slip - s0.plastic_slip, (1.0 - f) * 1e-7, 1e-15);  // eq. 3-15
  }
}

TEST(ContinuouslyYielding, ReversalFactorIsCappedAt075) {
  auto m = model("continuously_yielding", cy_report());
  ElementDriver d(*m);
  const ElementStage st = cnl(3e6, ShearPath::cycles(0.01, 1, 1e-4));
  d.begin_stage(st);
  for (int i = 0; i < 300; ++i) d.step(st, 1e-5, 0.0);  // close to the bound
  d.step(st, -1e-7, 0.0);                                 // reversal: r = tau/tau_o < 0
  auto s = law_state<ContinuouslyYielding::State>(d.state());
  EXPECT_LT(s.r, -0.75);
  d.step(st, 1e-7, 0.0);  // reversal again: tau/tau_o ~ 0.99 in this direction -> capped
  s = law_state<ContinuouslyYielding::State>(d.state());
  EXPECT_EQ(s.r, 0.75);
}

TEST(ContinuouslyYielding, DilationAngleAtTheBoundIsPhiMMinusPhiEq317) {
  auto m = model("continuously_yielding", cy_report());
  const auto p = bind_cy(cy_report());
  ElementDriver d(*m);
  const ElementStage st = cnl(3e6, ShearPath::cycles(0.01, 1, 1e-4));
  d.begin_stage(st);
  for (int i = 0; i < 2000; ++i) d.step(st, 1e-5, 0.0);  // 20 mm: stress at the bound
  const auto s0 = law_state<ContinuouslyYielding::State>(d.state());
  d.step(st, 1e-6, 0.0);
  const auto s1 = law_state<ContinuouslyYielding::State>(d.state());
  const double psi = std::atan(std::abs(s0.tau) / s0.sigma_n) - p.friction;  // eq. 3-16
  EXPECT_NEAR((s1.dilation - s0.dilation) / (s1.plastic_slip - s0.plastic_slip), std::tan(psi), 1e-9);
  EXPECT_NEAR(psi, ContinuouslyYielding::phi_m(p, s0.plastic_slip) - p.friction, 2e-3 * kDeg * 100);
}

TEST(ContinuouslyYielding, InconsistentStiffnessBoundsAreErrors) {
  try {
    bind_cy(cy_report({{"kn_min", "60 GPa/m"}, {"kn_max", "50 GPa/m"}}));
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("kn_min"), std::string::npos) << e.what();
  }
  EXPECT_THROW(bind_cy(values({{"kn", "30 GPa/m"}, {"kn_exponent", "0.7"}, {"ks", "30 GPa/m"},
                            {"initial_friction", "40 deg"}, {"friction", "33 deg"}, {"roughness", "0.02 m"}})),
               InputError);
  // Table 4-4 test 14 as printed (minjkn above jkn) is valid: the minimum governs.
  const auto p = bind_cy(cy_report({{"kn", "39.141 GPa/m"}, {"kn_min", "57.405 GPa/m"}, {"kn_max", "95 GPa/m"}}));
  EXPECT_NEAR(ContinuouslyYielding::normal_stiffness(p, 1e6), 57.405e9, 1.0);
}
