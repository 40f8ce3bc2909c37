// directional_wear: the fresh side past the mated position gives a second peak in the third
// quadrant of the first cycle.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "tests/unit/effect_test_util.hpp"

using namespace rockdem;
using namespace rockdem::testutil;

namespace {

// Rows of the third quadrant of cycle `c` (0-based) of a two-sided cycles record: from the first
// row past the origin going negative to the most negative offset.
struct Range {
  std::size_t from, to;
};
Range third_quadrant(const MeasurementFile& f, int c) {
  int seen = -1;
  for (std::size_t i = 1; i < f.rows.size(); ++i) {
    if (f.rows[i - 1].shear_disp_mm >= 0.0 && f.rows[i].shear_disp_mm < 0.0 && ++seen == c) {
      std::size_t j = i;
      while (j + 1 < f.rows.size() && f.rows[j + 1].shear_disp_mm < f.rows[j].shear_disp_mm) ++j;
      return {i, j + 1};
    }
  }
  return {0, 0};
}

struct Peak {
  double entry, peak, exit, at_mm;
};
// |tau| at the start and end of a range and its largest value inside.
Peak peak_in(const MeasurementFile& f, Range r) {
  Peak p{std::abs(f.rows[r.from].shear_stress_MPa), 0.0, std::abs(f.rows[r.to - 1].shear_stress_MPa), 0.0};
  for (std::size_t i = r.from; i < r.to; ++i) {
    if (std::abs(f.rows[i].shear_stress_MPa) > p.peak) {
      p.peak = std::abs(f.rows[i].shear_stress_MPa);
      p.at_mm = f.rows[i].shear_disp_mm;
    }
  }
  return p;
}

}  // namespace

TEST(EffectDirectionalWear, DisabledLeavesEveryLawBitForBitIdentical) {
  expect_disabled_is_bit_identical({effect("directional_wear", {{"enabled", "false"}, {"bins", "16"}})});
}

// Two +-10 mm cycles at 3 MPa. With the effect, the third quadrant of cycle 1 has an interior peak
// at least 5 % above both its entry and its end, within 3 % of the first-quadrant peak (the same
// virgin surface); cycle 2's third quadrant has no such fresh peak (below cycle 1's). Without
// the effect, the third quadrant has no interior peak.
TEST(EffectDirectionalWear, SecondPeakInTheThirdQuadrantOfTheFirstCycle) {
  const std::vector<std::pair<const char*, RawValues>> laws = {{"barton_bandis", bb_report()},
                                                                {"continuously_yielding", cy_report()}};
  for (const auto& [law, params] : laws) {
    for (const char* bins : {"2", "16"}) {
      auto m = model(law, params, {effect("directional_wear", {{"bins", bins}, {"extent", "20 mm"}})});
      ElementDriver d(*m);
      const auto f = d.run({cnl(3e6, ShearPath::cycles(0.01, 2, 1e-4))});
      const double first_peak = max_tau(f, 0, row_at(f, 10.0));
      const Peak q3 = peak_in(f, third_quadrant(f, 0));
      EXPECT_GT(q3.peak, 1.05 * q3.entry) << law << " bins " << bins;
      EXPECT_GT(q3.peak, 1.05 * q3.exit) << law << " bins " << bins;
      EXPECT_NEAR(q3.peak, first_peak, 0.03 * first_peak) << law << " bins " << bins;
      EXPECT_LT(q3.at_mm, -0.01) << law;
      const Peak q3b = peak_in(f, third_quadrant(f, 1));
      EXPECT_LT(q3b.peak, q3.peak - 0.05) << law << " bins " << bins;
      std::printf("%s bins %s: Q1 peak %.4f, Q3 entry %.4f peak %.4f at %.3f mm exit %.4f; cycle-2 Q3 peak %.4f\n", law,
                  bins, first_peak, q3.entry, q3.peak, q3.at_mm, q3.exit, q3b.peak);
    }
    auto plain = model(law, params);
    ElementDriver dp(*plain);
    const auto g = dp.run({cnl(3e6, ShearPath::cycles(0.01, 2, 1e-4))});
    const Peak q3 = peak_in(g, third_quadrant(g, 0));
    std::printf("%s plain: Q3 entry %.4f peak %.4f at %.3f mm exit %.4f\n", law, q3.entry, q3.peak, q3.at_mm, q3.exit);
    EXPECT_LT(q3.peak, 1.01 * std::max(q3.entry, q3.exit)) << law << " plain";
  }
}

// The fresh side dilates like the first side did: over the first 8 mm past the origin of a
// +-10 mm cycle at 3 MPa the joint dilates within 10 % of what it dilated over the first 8 mm
// of the cycle. Continuously-Yielding's dilation follows its shear stress (eq. 3-16), so the
// raised strength raises it; the effect scaling its rate as well made this 3.2 times as much (issue 15).
TEST(EffectDirectionalWear, TheFreshSideDilatesAsTheFirstSideDid) {
  const std::vector<std::pair<const char*, RawValues>> laws = {{"barton_bandis", bb_report()},
                                                                {"continuously_yielding", cy_report()}};
  for (const auto& [law, params] : laws) {
    auto m = model(law, params, {effect("directional_wear")});
    ElementDriver d(*m);
    const auto f = d.run({cnl(3e6, ShearPath::cycles(0.01, 1, 1e-4))});
    const std::size_t p8 = row_at(f, 8.0);
    const Range q3 = third_quadrant(f, 0);
    ASSERT_LT(p8, f.rows.size());
    ASSERT_LT(q3.from, q3.to);
    std::size_t n8 = q3.from;
    while (n8 < q3.to && f.rows[n8].shear_disp_mm > -8.0) ++n8;
    ASSERT_LT(n8, q3.to) << law;
    const double first = f.rows[p8].normal_disp_mm - f.rows[0].normal_disp_mm;
    const double fresh = f.rows[n8].normal_disp_mm - f.rows[q3.from].normal_disp_mm;
    std::printf("%s: dilation over the first 8 mm %.4f mm, over the first 8 mm past the origin %.4f mm\n", law, first, fresh);
    EXPECT_GT(first, 0.05) << law;
    EXPECT_NEAR(fresh, first, 0.10 * first) << law;
  }
}

// Resolved along the surface: after a +-5 mm cycle, a +-10 mm cycle meets surface beyond 5 mm for
// the first time; with 16 bins it is stronger there than with the two-sided bookkeeping, which
// counts all the earlier wear of that side.
TEST(EffectDirectionalWear, ResolvedBinsKeepSurfaceBeyondTheEarlierExcursionFresher) {
  auto run = [](const char* bins) {
    auto m = model("continuously_yielding", cy_report(),
                   {effect("directional_wear", {{"bins", bins}, {"extent", "20 mm"}})});
    ElementDriver d(*m);
    return d.run({cnl(3e6, ShearPath::cycles(0.005, 1, 1e-4)), cnl(3e6, ShearPath::cycles(0.01, 1, 1e-4))});
  };
  const auto sides = run("2"), resolved = run("16");
  const std::size_t stage2 = row_at(sides, 9.0, row_at(sides, 0.0, row_at(sides, -5.0)));
  const std::size_t stage2r = row_at(resolved, 9.0, row_at(resolved, 0.0, row_at(resolved, -5.0)));
  ASSERT_LT(stage2, sides.rows.size());
  EXPECT_GT(resolved.rows[stage2r].shear_stress_MPa, sides.rows[stage2].shear_stress_MPa + 0.02);
}

// Mohr-Coulomb has no wear: nothing to redistribute, the record is the plain law's.
TEST(EffectDirectionalWear, MohrCoulombUnchanged) {
  auto m = model("mohr_coulomb", mc_report(), {effect("directional_wear", {{"bins", "16"}})});
  auto plain = model("mohr_coulomb", mc_report());
  ElementDriver a(*m), b(*plain);
  const auto f = a.run({cnl(3e6, ShearPath::cycles(0.01, 1, 1e-4))});
  const auto g = b.run({cnl(3e6, ShearPath::cycles(0.01, 1, 1e-4))});
  ASSERT_EQ(f.rows.size(), g.rows.size());
  for (std::size_t i = 0; i < f.rows.size(); ++i) ASSERT_EQ(f.rows[i].shear_stress_MPa, g.rows[i].shear_stress_MPa);
}

TEST(EffectDirectionalWear, BinsMustBeEvenUpToSixteen) {
  EXPECT_THROW(model("mohr_coulomb", mc_report(), {effect("directional_wear", {{"bins", "3"}})}), InputError);
  EXPECT_THROW(model("mohr_coulomb", mc_report(), {effect("directional_wear", {{"bins", "18"}})}), InputError);
}
