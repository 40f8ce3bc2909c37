#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <numbers>

#include "tests/unit/effect_test_util.hpp"

using namespace rockdem;
using namespace rockdem::testutil;

// An effect switched off must leave every law's results identical, bit for bit: stresses, state
// and dissipation, along a path with loading, cycles, separation and re-contact.
TEST(StrengthReduction, DisabledLeavesEveryLawBitForBitIdentical) {
  expect_disabled_is_bit_identical({effect("strength_reduction", {{"enabled", "false"}, {"factor", "2.5"}})});
}

TEST(StrengthReduction, DividesTheStrengthByTheFactor) {
  // Mohr-Coulomb without dilation: the plateau is exactly sigma_n tan(phi) / SRF.
  auto m = model("mohr_coulomb", mc_report({{"dilation_angle", "0 deg"}}),
                 {EffectSpec{"strength_reduction", values({{"factor", "1.6"}}), "test"}});
  ElementDriver d(*m);
  const auto f = d.run({cnl(3e6, ShearPath::cycles(0.01, 1, 1e-4))});
  const double expected = 3.0 * std::tan(38.0 * std::numbers::pi / 180.0) / 1.6;
  EXPECT_NEAR(max_tau(f, 0, f.rows.size()), expected, 1e-9);
  EXPECT_NEAR(min_tau(f, 0, f.rows.size()), -expected, 1e-9);
  // With dilation, under constant normal stress the reduced plateau still holds closely.
  auto md = model("mohr_coulomb", mc_report(), {EffectSpec{"strength_reduction", values({{"factor", "1.6"}}), "test"}});
  ElementDriver dd(*md);
  const auto g = dd.run({cnl(3e6, ShearPath::cycles(0.01, 1, 1e-4))});
  EXPECT_NEAR(max_tau(g, 0, g.rows.size()), expected, 1e-4);
  // Two effects compose in order: two factors of 1.25 and 1.28 make 1.6.
  auto m2 = model("mohr_coulomb", mc_report({{"dilation_angle", "0 deg"}}),
                  {EffectSpec{"strength_reduction", values({{"factor", "1.25"}}), "a"},
                   EffectSpec{"strength_reduction", values({{"factor", "1.28"}}), "b"}});
  ElementDriver d2(*m2);
  const auto h = d2.run({cnl(3e6, ShearPath::cycles(0.01, 1, 1e-4))});
  EXPECT_NEAR(max_tau(h, 0, h.rows.size()), expected, 1e-9);
  EXPECT_EQ(m2->description(), "mohr_coulomb + strength_reduction + strength_reduction");
}

TEST(StrengthReduction, FactorOutOfRangeIsAnErrorWithTheRange) {
  try {
    model("mohr_coulomb", mc_report(), {EffectSpec{"strength_reduction", values({{"factor", "0"}}), "case.toml:9"}});
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("valid range is [0.001, 1000]"), std::string::npos) << e.what();
  }
  try {
    model("mohr_coulomb", mc_report(), {EffectSpec{"no_such_effect", {}, "case.toml:9"}});
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("valid names: "), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("strength_reduction"), std::string::npos) << e.what();
  }
}
