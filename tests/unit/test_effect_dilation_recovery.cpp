// dilation_recovery: the dilation returns to the residual at the mated position, below the
// forward curve.
#include <gtest/gtest.h>

#include <cmath>

#include "tests/unit/effect_test_util.hpp"

using namespace rockdem;
using namespace rockdem::testutil;

namespace {
double dilation(const MeasurementFile& f, std::size_t i) { return f.extra[i][0]; }  // dilation_mm
}  // namespace

TEST(EffectDilationRecovery, DisabledLeavesEveryLawBitForBitIdentical) {
  expect_disabled_is_bit_identical({effect("dilation_recovery", {{"enabled", "false"}, {"residual_fraction", "0.3"}})});
}

// All three laws with the report's "Dilation 1" (dilation keeps growing on reverse shearing):
// with the effect, after 0 -> 10 mm -> 0 at 3 MPa the dilation is back to rho * d_reversal at the
// mated position, and on the way back it lies below the forward curve at every offset from 1 to
// 9 mm; without it the dilation at the origin is at least that at the reversal.
TEST(EffectDilationRecovery, ReturnsToTheResidualBelowTheForwardCurve) {
  const std::vector<std::pair<const char*, RawValues>> laws = {
      {"mohr_coulomb", mc_report()}, {"barton_bandis", bb_report()}, {"continuously_yielding", cy_report()}};
  for (const auto& [law, params] : laws) {
    for (const double rho : {0.0, 0.25}) {
      auto m = model(law, params, {effect("dilation_recovery", {{"residual_fraction", std::to_string(rho)}})});
      ElementDriver d(*m);
      const auto f = d.run({cnl(3e6, ShearPath::cycles(0.01, 1, 1e-4, true))});
      const std::size_t rev = first_reverse_row(f);
      const double d_rev = dilation(f, rev - 1);
      ASSERT_GT(d_rev, 0.01) << law;
      EXPECT_NEAR(dilation(f, f.rows.size() - 1), rho * d_rev, 0.02 * d_rev) << law << " rho " << rho;
      for (double u = 1.0; u <= 9.0; u += 1.0) {
        const std::size_t fw = row_at(f, u), bw = row_at(f, u, rev);
        ASSERT_LT(bw, f.rows.size());
        if (dilation(f, fw) > rho * d_rev + 0.02 * d_rev) {
          EXPECT_LT(dilation(f, bw), dilation(f, fw)) << law << " at " << u << " mm, rho " << rho;
        }
      }
      // and the normal displacement under constant normal stress follows the dilation
      EXPECT_NEAR(f.rows.back().normal_disp_mm, dilation(f, f.rows.size() - 1), 1e-3) << law;
    }
    auto plain = model(law, params);
    ElementDriver dp(*plain);
    const auto g = dp.run({cnl(3e6, ShearPath::cycles(0.01, 1, 1e-4, true))});
    EXPECT_GE(dilation(g, g.rows.size() - 1), dilation(g, first_reverse_row(g) - 1)) << law;
  }
}

// The return path has the prescribed shape once the elastic lag of the reversal is caught up:
// Mohr-Coulomb, h = 1, rho = 0: d = d_r x^2 at x = 0.5 (5 mm) within 1 %.
TEST(EffectDilationRecovery, ReturnPathFollowsTheShapeFunction) {
  auto m = model("mohr_coulomb", mc_report(), {effect("dilation_recovery")});
  ElementDriver d(*m);
  const auto f = d.run({cnl(3e6, ShearPath::cycles(0.01, 1, 1e-4, true))});
  const std::size_t rev = first_reverse_row(f);
  const double d_rev = dilation(f, rev - 1);
  const std::size_t half = row_at(f, 5.0, rev);
  EXPECT_NEAR(dilation(f, half), 0.25 * d_rev, 0.01 * d_rev);
}
