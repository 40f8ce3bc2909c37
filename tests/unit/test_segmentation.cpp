// Segmentation of shear records into monotonic segments, cycles and quadrants: exact counts on
// synthetic paths, with noise below the reversal threshold that must not create segments.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "framework/analysis/segmentation.hpp"

using namespace rockdem;

namespace {

// Appends rows of `stage` sweeping linearly through `waypoints` [mm] in steps of about `du`.
void sweep(MeasurementFile& f, int stage, double sigma, const std::vector<double>& waypoints, double du) {
  double t = f.rows.empty() ? 0.0 : f.rows.back().time_s;
  f.rows.push_back({t, stage, sigma, waypoints.front(), 0.0, 0.0});
  for (std::size_t k = 1; k < waypoints.size(); ++k) {
    const double a = waypoints[k - 1], b = waypoints[k];
    const int n = std::max(1, static_cast<int>(std::ceil(std::abs(b - a) / du)));
    for (int i = 1; i <= n; ++i) {
      t += 1.0;
      f.rows.push_back({t, stage, sigma, a + (b - a) * i / n, 0.0, 0.0});
    }
  }
}

// Quadrants of contiguous runs of rows within `stage`, in order.
std::vector<int> quadrant_runs(const Segmentation& s, int stage) {
  std::vector<int> q;
  for (const auto& l : s.labels) {
    if (l.stage != stage) continue;
    if (q.empty() || q.back() != l.quadrant) q.push_back(l.quadrant);
  }
  return q;
}

}  // namespace

TEST(Segmentation, OneSidedCycles) {
  MeasurementFile f;
  sweep(f, 1, 3.0, {0, 10, 0, 10, 0, 10, 0}, 0.05);
  const Segmentation s = segment(f);
  ASSERT_EQ(s.stages.size(), 1u);
  EXPECT_EQ(s.stages[0].segment_count, 6u);
  EXPECT_EQ(s.stages[0].cycles, 3);
  EXPECT_EQ(s.stages[0].first_side, 1);
  EXPECT_EQ(quadrant_runs(s, 1), (std::vector<int>{1, 4, 1, 4, 1, 4}));
  // 200 rows a stroke: row 450 is u = 2.5 mm going up again, in cycle 2.
  ASSERT_NEAR(f.rows[450].shear_disp_mm, 2.5, 1e-12);
  const RowLabel& l = s.labels[450];
  EXPECT_EQ(l.cycle, 2);
  EXPECT_EQ(l.quadrant, 1);
  EXPECT_EQ(l.direction, 1);
  EXPECT_EQ(l.motion, 1);
  EXPECT_EQ(l.segment, 2);
  // The turning point at 10 mm ends the forward segment; the return ends the cycle at 0.
  EXPECT_EQ(s.labels[200].quadrant, 1);
  EXPECT_EQ(s.labels[201].quadrant, 4);
  EXPECT_EQ(s.labels[400].cycle, 1);
  EXPECT_EQ(s.labels[401].cycle, 2);
  EXPECT_EQ(s.segments[1].curve_begin, 200u);
  EXPECT_EQ(s.segments[1].begin, 201u);
  EXPECT_DOUBLE_EQ(s.segments[1].u_start, 10.0);
  EXPECT_DOUBLE_EQ(s.segments[1].u_end, 0.0);
}

TEST(Segmentation, TwoSidedSinusoidWithNoise) {
  // 5 cycles of 12.7 mm amplitude, 400 samples a cycle, uniform noise of +-0.1 mm (the reversal
  // threshold is 2 % of the 25.4 mm range, 0.508 mm): the noise makes the samples non-monotonic
  // near every turning point and zero crossing, but must not add segments or flip quadrants.
  MeasurementFile f;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> noise(-0.1, 0.1);
  const int n = 5 * 400;
  for (int i = 0; i <= n; ++i) {
    const double u = 12.7 * std::sin(2.0 * std::numbers::pi * i / 400.0) + (i == 0 ? 0.0 : noise(rng));
    f.rows.push_back({0.01 * i, 1, 1.0, u, 0.0, 0.0});
  }
  const Segmentation s = segment(f);
  ASSERT_EQ(s.stages.size(), 1u);
  EXPECT_EQ(s.stages[0].segment_count, 11u);  // 0 -> +A, then 10 half-waves, the last back to 0
  EXPECT_EQ(s.stages[0].cycles, 5);
  std::vector<int> want;
  for (int c = 0; c < 5; ++c) want.insert(want.end(), {1, 4, 3, 2});
  EXPECT_EQ(quadrant_runs(s, 1), want);
  // Cycles begin where the path leaves the origin on the positive side.
  for (std::size_t i = 1; i < s.labels.size(); ++i) {
    if (s.labels[i].cycle != s.labels[i - 1].cycle) {
      EXPECT_EQ(s.labels[i].cycle, s.labels[i - 1].cycle + 1);
      EXPECT_EQ(s.labels[i].quadrant, 1);
      EXPECT_EQ(s.labels[i - 1].quadrant, 2);
      EXPECT_NEAR(f.rows[i].shear_disp_mm, 0.0, 0.6);
    }
  }
  // Forward = away from the origin, reverse = toward it, whatever the sign of motion.
  for (std::size_t i = 0; i < s.labels.size(); ++i) {
    const RowLabel& l = s.labels[i];
    EXPECT_EQ(l.direction, (l.quadrant == 1 || l.quadrant == 3) ? 1 : -1);
    EXPECT_EQ(l.motion, (l.quadrant == 1 || l.quadrant == 2) ? 1 : -1);
  }
}

TEST(Segmentation, MultiStageWithStationaryStage) {
  MeasurementFile f;
  sweep(f, 1, 2.0, {0, 40, 0}, 0.1);                  // one-sided, one cycle
  sweep(f, 2, 3.0, {0, 5, 0, -5, 0, 5, 0, -5, 0}, 0.01);  // two-sided, two cycles
  sweep(f, 3, 4.0, {0, 0}, 1.0);                      // normal loading only
  for (int i = 0; i < 20; ++i) f.rows.push_back({f.rows.back().time_s + 1, 3, 4.0, 0.0, 0.0, 0.0});
  const Segmentation s = segment(f);
  ASSERT_EQ(s.stages.size(), 3u);
  EXPECT_EQ(s.stages[0].segment_count, 2u);
  EXPECT_EQ(s.stages[0].cycles, 1);
  EXPECT_EQ(s.stages[1].segment_count, 5u);  // 0->5, 5->-5, -5->5, 5->-5, -5->0
  EXPECT_EQ(s.stages[1].cycles, 2);
  EXPECT_EQ(s.stages[2].segment_count, 1u);
  EXPECT_EQ(s.stages[2].first_side, 0);
  EXPECT_EQ(quadrant_runs(s, 1), (std::vector<int>{1, 4}));
  EXPECT_EQ(quadrant_runs(s, 2), (std::vector<int>{1, 4, 3, 2, 1, 4, 3, 2}));
  EXPECT_EQ(quadrant_runs(s, 3), (std::vector<int>{0}));
  EXPECT_DOUBLE_EQ(s.stages[1].normal_stress_MPa, 3.0);
  EXPECT_DOUBLE_EQ(s.stages[0].threshold, 0.02 * 40.0);
  EXPECT_DOUBLE_EQ(s.stages[1].threshold, 0.02 * 10.0);
  EXPECT_EQ(s.stages[1].begin, s.stages[0].end);
  EXPECT_EQ(s.find_stage(2)->stage, 2);
  EXPECT_EQ(s.find_stage(9), nullptr);
}

TEST(Segmentation, FirstStrokeNegativeAndPartialReversals) {
  MeasurementFile f;
  sweep(f, 1, 1.0, {0, -10, 0, 10, 0}, 0.05);
  // An earthquake-like stage: partial reversals that do not reach the origin stay in one cycle.
  sweep(f, 2, 1.0, {0, 10, 6, 12, 0, -8, -3, -9, 0}, 0.05);
  const Segmentation s = segment(f);
  EXPECT_EQ(s.stages[0].first_side, -1);
  EXPECT_EQ(s.stages[0].cycles, 1);
  EXPECT_EQ(quadrant_runs(s, 1), (std::vector<int>{3, 2, 1, 4}));
  EXPECT_EQ(s.stages[1].segment_count, 7u);  // 12 -> 0 -> -8 is one monotonic segment
  EXPECT_EQ(s.stages[1].cycles, 1);
  EXPECT_EQ(quadrant_runs(s, 2), (std::vector<int>{1, 4, 1, 4, 3, 2, 3, 2}));
}

TEST(Segmentation, SmallWigglesBelowThresholdAreNotReversals) {
  // A stroke with 0.3 mm back-steps every 5 mm (threshold 0.4 mm of a 20 mm range) stays one
  // segment; a 0.5 mm back-step is a reversal.
  MeasurementFile f;
  sweep(f, 1, 1.0, {0, 5, 4.7, 10, 9.7, 15, 14.7, 20, 0}, 0.05);
  EXPECT_EQ(segment(f).stages[0].segment_count, 2u);
  MeasurementFile g;
  sweep(g, 1, 1.0, {0, 5, 4.5, 20, 0}, 0.05);
  EXPECT_EQ(segment(g).stages[0].segment_count, 4u);
  // An explicit per-stage threshold overrides the fraction.
  SegmentationOptions o;
  o.threshold_mm[1] = 1.0;
  EXPECT_EQ(segment(g, o).stages[0].segment_count, 2u);
}
