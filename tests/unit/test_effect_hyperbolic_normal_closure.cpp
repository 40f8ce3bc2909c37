// hyperbolic_normal_closure: the closure curve of every law is the Bandis hyperbola.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "tests/unit/effect_test_util.hpp"

using namespace rockdem;
using namespace rockdem::testutil;

namespace {
constexpr double kKni = 20e9, kVm = 5e-5;
std::vector<std::pair<const char*, RawValues>> laws() {
  return {{"mohr_coulomb", mc_report()}, {"barton_bandis", bb_report()}, {"continuously_yielding", cy_report()}};
}
EffectSpec closure_effect() {
  return effect("hyperbolic_normal_closure", {{"initial_normal_stiffness", "20 GPa/m"}, {"max_closure", "0.05 mm"}});
}
}  // namespace

TEST(EffectHyperbolicNormalClosure, DisabledLeavesEveryLawBitForBitIdentical) {
  expect_disabled_is_bit_identical({effect("hyperbolic_normal_closure", {{"enabled", "false"}})});
}

// Closing a joint in 200 steps to 0.9 Vm and opening it again: sigma_n = Kni V/(1 - V/Vm) at
// every step (1e-9 relative), the tangent stiffness Kni/(1 - V/Vm)^2 reported as kn, and the
// time-step stiffness before the first update is Kni.
TEST(EffectHyperbolicNormalClosure, ClosureCurveIsTheBandisHyperbolaForEveryLaw) {
  for (const auto& [law, params] : laws()) {
    auto m = model(law, params, {closure_effect()});
    EXPECT_EQ(m->initial_kn(), kKni) << law;
    JointStateBlock s;
    m->init(s);
    JointResponse r;
    JointKinematics k;
    const int n = 200;
    const double dv = 0.9 * kVm / n;
    auto check = [&](double v) {
      const double expected = kKni * v / (1.0 - v / kVm);
      EXPECT_NEAR(r.sigma_n, expected, 1e-9 * expected + 1e-6) << law << " V = " << v;
      const double q = 1.0 - v / kVm;
      EXPECT_NEAR(r.kn, kKni / (q * q), 1e-6 * kKni / (q * q)) << law;
    };
    for (int i = 1; i <= n; ++i) {
      k.du_n = -dv;
      m->update(s, k, r);
      check(i * dv);
    }
    for (int i = n - 1; i >= 1; --i) {  // unloading follows the same curve (no hysteresis)
      k.du_n = dv;
      m->update(s, k, r);
      check(i * dv);
    }
  }
}

// Barton-Bandis has the hyperbola built in (normal_closure = "bandis"): the effect on the linear
// law must give the same record, row for row, through a sheared cycle with dilation.
TEST(EffectHyperbolicNormalClosure, MatchesBartonBandisBuiltInClosure) {
  auto built_in = model("barton_bandis", bb_report({{"normal_closure", "bandis"}, {"initial_normal_stiffness", "20 GPa/m"},
                                                    {"max_closure", "0.05 mm"}, {"dilation", "reversible"}}));
  auto with_effect = model("barton_bandis", bb_report({{"dilation", "reversible"}}), {closure_effect()});
  ElementDriver a(*built_in), b(*with_effect);
  const auto fa = a.run({cnl(3e6, ShearPath::cycles(0.005, 1, 1e-4))});
  const auto fb = b.run({cnl(3e6, ShearPath::cycles(0.005, 1, 1e-4))});
  ASSERT_EQ(fa.rows.size(), fb.rows.size());
  for (std::size_t i = 0; i < fa.rows.size(); ++i) {
    ASSERT_EQ(fa.rows[i].shear_stress_MPa, fb.rows[i].shear_stress_MPa) << i;
    ASSERT_EQ(fa.rows[i].normal_disp_mm, fb.rows[i].normal_disp_mm) << i;
  }
}

// Shear is untouched: the Mohr-Coulomb plateau under constant normal stress stays 3 tan 38 deg,
// and the dilation under constant normal stress is the same; only the closure differs.
TEST(EffectHyperbolicNormalClosure, ShearStrengthUnchanged) {
  auto m = model("mohr_coulomb", mc_report(), {closure_effect()});
  auto plain = model("mohr_coulomb", mc_report());
  ElementDriver d(*m), dp(*plain);
  const auto f = d.run({cnl(3e6, ShearPath::cycles(0.005, 1, 1e-4, true))});
  const auto g = dp.run({cnl(3e6, ShearPath::cycles(0.005, 1, 1e-4, true))});
  EXPECT_NEAR(max_tau(f, 0, f.rows.size()), 3.0 * std::tan(38.0 * std::numbers::pi / 180.0), 1e-6);
  EXPECT_EQ(d.unconverged_steps(), 0);
  const std::size_t at5 = row_at(f, 5.0), at5p = row_at(g, 5.0);
  ASSERT_LT(at5, f.rows.size());
  EXPECT_NEAR(f.rows[at5].normal_disp_mm, g.rows[at5p].normal_disp_mm, 1e-6);
}
