// Model/measurement comparison: alignment on shear displacement (exact for piecewise-linear
// curves whatever the sampling and time base), metric values, worst-segment lines, refusals.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "framework/analysis/compare.hpp"
#include "framework/core/error.hpp"

using namespace rockdem;

namespace {

// A record defined by piecewise-linear curves along the path: each segment runs through its
// knots (u [mm], shear stress [MPa], normal displacement [mm]) in path order; consecutive segments
// share their turning knot, so the curves are continuous as a measured record is.
struct Knot {
  double u, tau, dn;
};
struct StageDef {
  int stage;
  double sigma;
  std::vector<std::vector<Knot>> segments;
};

Knot at(const std::vector<Knot>& k, double u) {
  const double dir = k.back().u > k.front().u ? 1.0 : -1.0;
  for (std::size_t i = 1; i < k.size(); ++i) {
    if (dir * u <= dir * k[i].u) {
      const double t = (u - k[i - 1].u) / (k[i].u - k[i - 1].u);
      return {u, k[i - 1].tau + t * (k[i].tau - k[i - 1].tau), k[i - 1].dn + t * (k[i].dn - k[i - 1].dn)};
    }
  }
  return k.back();
}

// model = true: samples on a grid of `step` plus every knot (so linear interpolation between the
// samples is exact); false: `n` random positions a segment. dt: time between rows.
MeasurementFile make(const std::vector<StageDef>& stages, bool model, double step, int n, double dt,
                     unsigned seed = 1) {
  MeasurementFile f;
  std::mt19937 rng(seed);
  double t = 0.0;
  for (const auto& st : stages) {
    const Knot k0 = st.segments.front().front();
    f.rows.push_back({t, st.stage, st.sigma, k0.u, k0.tau, k0.dn});
    for (const auto& seg : st.segments) {
      const double a = seg.front().u, b = seg.back().u, dir = b > a ? 1.0 : -1.0;
      std::vector<double> us;
      if (model) {
        for (double x = a + dir * step; dir * x < dir * b; x += dir * step) us.push_back(x);
        for (std::size_t i = 1; i < seg.size(); ++i) us.push_back(seg[i].u);
      } else {
        std::uniform_real_distribution<double> pos(std::min(a, b), std::max(a, b));
        for (int i = 0; i < n; ++i) us.push_back(pos(rng));
        us.push_back(b);
      }
      std::sort(us.begin(), us.end(), [dir](double x, double y) { return dir * x < dir * y; });
      us.erase(std::unique(us.begin(), us.end()), us.end());
      for (double u : us) {
        t += dt;
        const Knot v = at(seg, u);
        f.rows.push_back({t, st.stage, st.sigma, u, v.tau, v.dn});
      }
    }
  }
  return f;
}

// Test 9-like: two stages, each 0 -> +A -> 0; the second stage two-sided and two cycles.
std::vector<StageDef> path(double amplitude = 40.0, double sigma2 = 4.0) {
  const double A = amplitude;
  StageDef s1{1, 3.0,
              {{{0, 0, 0}, {1.5, 2.2, -0.01}, {A / 2, 2.4, 0.5}, {A, 2.3, 0.9}},
               {{A, 2.3, 0.9}, {A - 1, -1.6, 0.88}, {A / 3, -2.0, 0.4}, {0, -1.9, 0.1}}}};
  StageDef s2{2, sigma2, {}};
  for (int c = 0; c < 2; ++c) {
    s2.segments.push_back({{0, 0, 0.1}, {1.0, 2.8, 0.09}, {A / 2, 3.0, 0.4}});
    s2.segments.push_back({{A / 2, 3.0, 0.4}, {A / 2 - 1, -2.5, 0.38}, {0, -2.7, 0.1}, {-A / 2, -2.9, 0.35}});
    s2.segments.push_back({{-A / 2, -2.9, 0.35}, {-A / 2 + 1, 2.6, 0.33}, {0, 2.7, 0.1}});
  }
  // Join the cycles: each segment starts where the last one ended (-A/2 -> 0 -> +A/2 is one).
  std::vector<std::vector<Knot>> joined;
  for (auto& s : s2.segments) {
    if (!joined.empty() && (joined.back().back().u - joined.back().front().u) * (s.back().u - s.front().u) > 0) {
      joined.back().insert(joined.back().end(), s.begin() + 1, s.end());
    } else {
      joined.push_back(s);
    }
  }
  s2.segments = joined;
  return {s1, s2};
}

void expect_refused(const MeasurementFile& d, const MeasurementFile& m, const std::vector<std::string>& words) {
  try {
    compare(d, m);
    ADD_FAILURE() << "accepted incompatible records";
  } catch (const InputError& e) {
    for (const auto& w : words) EXPECT_NE(std::string(e.what()).find(w), std::string::npos) << e.what();
  }
}

}  // namespace

TEST(Compare, IdenticalRecordsHaveZeroError) {
  const MeasurementFile d = make(path(), false, 0.0, 500, 1.0);
  const Comparison c = compare(d, d);
  for (std::size_t v = 0; v < 2; ++v) {
    EXPECT_EQ(c.overall.var[v].n, d.rows.size());
    EXPECT_EQ(c.overall.var[v].rmse, 0.0);
    EXPECT_EQ(c.overall.var[v].bias, 0.0);
    for (const auto& g : c.segments) EXPECT_EQ(g.var[v].rmse, 0.0);
  }
  EXPECT_EQ(c.combined_nrmse, 0.0);
  EXPECT_EQ(c.alignment.outside, 0u);
  EXPECT_EQ(c.stages.size(), 2u);
  EXPECT_EQ(c.cycles.size(), 3u);  // stage 1: one cycle, stage 2: two
  // Quadrants in the report's order of a cycle.
  ASSERT_EQ(c.quadrants.size(), 4u);
  EXPECT_EQ(c.quadrants[0].quadrant, 1);
  EXPECT_EQ(c.quadrants[1].quadrant, 4);
  EXPECT_EQ(c.quadrants[2].quadrant, 3);
  EXPECT_EQ(c.quadrants[3].quadrant, 2);
  EXPECT_EQ(c.segments.size(), 2u + 8u);  // stage 1: Q1, Q4; stage 2: 2 cycles x 4
}

TEST(Compare, KnownOffsetGivesExactBiasAndRmse) {
  const MeasurementFile d = make(path(), false, 0.0, 400, 1.0);
  MeasurementFile m = d;
  for (auto& r : m.rows) {
    r.shear_stress_MPa += 0.25;
    r.normal_disp_mm -= 0.1;
  }
  const Comparison c = compare(d, m);
  double lo = 1e300, hi = -1e300;
  for (const auto& r : d.rows) {
    lo = std::min(lo, r.shear_stress_MPa);
    hi = std::max(hi, r.shear_stress_MPa);
  }
  EXPECT_NEAR(c.overall.var[0].bias, 0.25, 1e-12);
  EXPECT_NEAR(c.overall.var[0].rmse, 0.25, 1e-12);
  EXPECT_NEAR(c.overall.var[0].nrmse, 0.25 / (hi - lo), 1e-12);
  EXPECT_NEAR(c.overall.var[1].bias, -0.1, 1e-12);
  EXPECT_NEAR(c.overall.var[1].rmse, 0.1, 1e-12);
  EXPECT_NEAR(c.combined_nrmse, 0.5 * (c.overall.var[0].nrmse + c.overall.var[1].nrmse), 1e-15);
  for (const auto& g : c.quadrants) EXPECT_NEAR(g.var[0].bias, 0.25, 1e-12);
  const nlohmann::json j = to_json(c);
  EXPECT_NEAR(j["nrmse"]["shear_stress"].get<double>(), 0.25 / (hi - lo), 1e-12);
  EXPECT_EQ(j["segments"].size(), 2u * c.segments.size());
  EXPECT_EQ(j["segments"][0]["variable"], "shear_stress");
}

TEST(Compare, AlignmentIsExactAcrossSamplingAndTimeBase) {
  // The measurement: random positions, one row a second. The model: a 0.37 mm grid plus the
  // knots, a thousand times faster. Matching by time would be meaningless; by displacement within
  // the segment it is exact for these piecewise-linear curves.
  const MeasurementFile d = make(path(), false, 0.0, 3000, 1.0, 11);
  const MeasurementFile m = make(path(), true, 0.37, 0, 1e-3);
  ASSERT_NE(d.rows.size(), m.rows.size());
  const Comparison c = compare(d, m);
  EXPECT_LT(c.overall.var[0].rmse, 1e-12);
  EXPECT_LT(c.overall.var[1].rmse, 1e-12);
  EXPECT_EQ(c.alignment.outside, 0u);
  // And the other way round (model sparse, measurement dense is the usual case; both must work).
  const Comparison r = compare(m, d);
  EXPECT_GT(r.overall.var[0].rmse, 0.0);  // random samples miss the knots: not exact, but close
  EXPECT_LT(r.overall.var[0].rmse, 0.05);
}

TEST(Compare, QuadrantOffsetIsLocalisedAndWorded) {
  const MeasurementFile d = make(path(), false, 0.0, 400, 1.0);
  const Segmentation s = segment(d);
  MeasurementFile m = d;
  double abs_sum = 0.0, mag_sum = 0.0;
  std::size_t n = 0;
  for (std::size_t i = 0; i < m.rows.size(); ++i) {
    if (s.labels[i].stage == 1 && s.labels[i].quadrant == 4) {
      m.rows[i].shear_stress_MPa += 0.5;
      abs_sum += std::abs(d.rows[i].shear_stress_MPa);
      mag_sum += std::abs(m.rows[i].shear_stress_MPa) - std::abs(d.rows[i].shear_stress_MPa);
      ++n;
    }
  }
  // Reverse shearing of stage 1 is mostly at negative stress: +0.5 MPa there is a smaller magnitude.
  const double mag = mag_sum / static_cast<double>(n);
  ASSERT_LT(mag, -0.25);
  const Comparison c = compare(d, s, m);
  for (const auto& g : c.segments) {
    const bool hit = g.stage == 1 && g.quadrant == 4;
    EXPECT_NEAR(g.var[0].bias, hit ? 0.5 : 0.0, 1e-12) << g.stage << " " << g.cycle << " " << g.quadrant;
    EXPECT_EQ(g.var[1].rmse, 0.0);
  }
  ASSERT_FALSE(c.worst.empty());
  char pct[32], head[160];
  std::snprintf(pct, sizeof pct, "(%.0f %%", 100.0 * -mag / (abs_sum / static_cast<double>(n)));
  std::snprintf(head, sizeof head,
                "stage 1, cycle 1, reverse shearing (quadrant 4): shear stress under-predicted by %.3g MPa in magnitude",
                -mag);
  for (const auto& g : c.segments) {
    if (g.stage == 1 && g.quadrant == 4) {
      EXPECT_NEAR(g.var[0].magnitude_bias, mag, 1e-12);
    }
  }
  const std::string& w = c.worst.front();
  EXPECT_NE(w.find(head), std::string::npos) << w << " lacks " << head;
  EXPECT_NE(w.find(pct), std::string::npos) << w << " lacks " << pct;
  EXPECT_NE(w.find("measured mean magnitude"), std::string::npos) << w;
}

TEST(Compare, RefusesDifferentStages) {
  const MeasurementFile d = make(path(), false, 0.0, 100, 1.0);
  MeasurementFile m = d;
  m.rows.erase(std::remove_if(m.rows.begin(), m.rows.end(), [](const MeasurementRow& r) { return r.stage == 2; }),
               m.rows.end());
  expect_refused(d, m, {"different stages", "measurement has stage(s) 1, 2", "the model 1"});
}

TEST(Compare, RefusesDifferentAmplitude) {
  const MeasurementFile d = make(path(40.0), false, 0.0, 100, 1.0);
  const MeasurementFile m = make(path(10.0), true, 0.5, 0, 1.0);
  expect_refused(d, m, {"stage 1", "different shear paths", "+40 mm", "+10 mm"});
}

TEST(Compare, RefusesDifferentCycleCountAndOppositeFirstStroke) {
  StageDef one{1, 3.0, {{{0, 0, 0}, {10, 1, 0.1}}, {{10, 1, 0.1}, {0, -1, 0}}}};
  StageDef two = one;
  two.segments.push_back({{0, -1, 0}, {10, 1, 0.1}});
  two.segments.push_back({{10, 1, 0.1}, {0, -1, 0}});
  const MeasurementFile d = make({one}, false, 0.0, 100, 1.0);
  expect_refused(d, make({two}, true, 0.5, 0, 1.0),
                 {"stage 1", "measurement has 1 reversal (1 cycle)", "the model 3 reversals (2 cycles)"});
  StageDef neg{1, 3.0, {{{0, 0, 0}, {-10, -1, 0.1}}, {{-10, -1, 0.1}, {0, 1, 0}}}};
  expect_refused(d, make({neg}, true, 0.5, 0, 1.0),
                 {"opposite first strokes", "measurement first shears toward the positive side", "model toward the negative"});
}

TEST(Compare, RefusesDifferentNormalStress) {
  const MeasurementFile d = make(path(40.0, 4.0), false, 0.0, 100, 1.0);
  const MeasurementFile m = make(path(40.0, 5.0), true, 0.5, 0, 1.0);
  expect_refused(d, m, {"stage 2", "different normal stress", "4 MPa", "5 MPa"});
}

TEST(Compare, AcceptsSmallEndPointDifferences) {
  // The model stops 0.6 mm short of the measured 40 mm (tolerance 10 % of 40 mm): compared, with
  // the measured rows beyond the model's end counted.
  const MeasurementFile d = make(path(40.0), false, 0.0, 1000, 1.0);
  const MeasurementFile m = make(path(39.4), true, 0.2, 0, 1.0);
  const Comparison c = compare(d, m);
  EXPECT_GT(c.alignment.outside, 0u);
  EXPECT_LT(c.alignment.outside, d.rows.size() / 20);
  EXPECT_TRUE(std::isfinite(c.combined_nrmse));
  CompareOptions strict;
  strict.endpoint_tolerance = 0.01;
  EXPECT_THROW(compare(d, m, strict), InputError);
}

TEST(Compare, SmallReversalsWithinASegmentAreAlignedPieceByPiece) {
  // An earthquake-like stroke: 0.2-0.3 mm back-steps at 10 mm, below the 0.4 mm reversal threshold
  // (2 % of 20 mm), so 0 -> 20 mm stays one segment; the shear stress flips at each back-step as
  // a rigid-plastic joint's does. Matching the finer reversals of both records keeps the
  // alignment exact; first passage over the whole segment would put the flipped stress of a
  // back-step against the forward stress.
  StageDef st{1, 1.0,
              {{{0, 0, 0}, {0.05, 1, 0}, {10, 1, 0.5}},
               {{10, 1, 0.5}, {9.95, -1, 0.49}, {9.8, -1, 0.48}},
               {{9.8, -1, 0.48}, {9.85, 1, 0.485}, {10.1, 1, 0.5}},
               {{10.1, 1, 0.5}, {10.05, -1, 0.49}, {9.9, -1, 0.48}},
               {{9.9, -1, 0.48}, {9.95, 1, 0.49}, {20, 1, 1.0}},
               {{20, 1, 1.0}, {19.95, -1, 0.99}, {0, -1, 0.1}}}};
  const MeasurementFile d = make({st}, false, 0.0, 300, 1.0, 5);
  const MeasurementFile m = make({st}, true, 0.013, 0, 1e-3);
  ASSERT_EQ(segment(d).stages[0].segment_count, 2u);
  const Comparison c = compare(d, m);
  EXPECT_EQ(c.alignment.finely_aligned_segments, 1u);
  EXPECT_LT(c.overall.var[0].rmse, 1e-12);
  EXPECT_LT(c.overall.var[1].rmse, 1e-12);
  CompareOptions coarse;
  coarse.fine_fraction = 0.0;
  EXPECT_GT(compare(d, m, coarse).overall.var[0].rmse, 0.1);
}

TEST(Compare, ReversalSeenInOneRecordOnlyRaisesTheThreshold) {
  // A 0.35 mm back-step in the measurement (below the 0.4 mm threshold: no reversal) is 0.45 mm in
  // the model (a reversal): the records agree from a 0.6 mm threshold on, and are compared there.
  auto stage = [](double back) {
    return StageDef{1, 1.0,
                    {{{0, 0, 0}, {0.1, 1, 0}, {10, 1, 0.5}},
                     {{10, 1, 0.5}, {10 - back, -1, 0.49}},
                     {{10 - back, -1, 0.49}, {10 - back + 0.1, 1, 0.5}, {20, 1, 1.0}},
                     {{20, 1, 1.0}, {19.9, -1, 0.99}, {0, -1, 0.1}}}};
  };
  const MeasurementFile d = make({stage(0.35)}, false, 0.0, 400, 1.0, 3);
  const MeasurementFile m = make({stage(0.45)}, true, 0.05, 0, 1e-3);
  ASSERT_EQ(segment(d).stages[0].segment_count, 2u);
  ASSERT_EQ(segment(m).stages[0].segment_count, 4u);
  const Comparison c = compare(d, m);
  ASSERT_EQ(c.notes.size(), 1u);
  EXPECT_NE(c.notes[0].find("stage 1: reversal threshold raised from 0.4 mm to 0.6 mm"), std::string::npos)
      << c.notes[0];
  EXPECT_NE(c.notes[0].find("the measurement has 1 reversal (1 cycle), the model 3 reversals"), std::string::npos)
      << c.notes[0];
  EXPECT_DOUBLE_EQ(c.data_segments.stages[0].threshold, 0.6);
  EXPECT_EQ(c.model_segments.stages[0].segment_count, 2u);
  EXPECT_TRUE(std::isfinite(c.combined_nrmse));
  // Only rows near the back-step differ; the rest of the stroke and the return align exactly.
  EXPECT_LT(c.overall.var[1].rmse, 0.01);
}

TEST(Compare, APlacementServesAnotherModelRecordAlongTheSamePath) {
  // Calibration keeps where align() put the measured rows (Alignment::rows) and reads a later
  // run's values there: for a record along the same path with other stresses and dilation, that
  // must be what aligning it afresh gives, to the bit.
  const MeasurementFile d = make(path(), false, 0.0, 300, 1.0, 3);
  const MeasurementFile m1 = make(path(), true, 0.37, 0, 0.5);
  MeasurementFile m2 = m1;
  for (std::size_t j = 0; j < m2.rows.size(); ++j) {
    m2.rows[j].shear_stress_MPa = 1.3 * m2.rows[j].shear_stress_MPa + 0.01 * std::sin(0.1 * static_cast<double>(j));
    m2.rows[j].normal_disp_mm *= 0.7;
  }
  const Segmentation ds = segment(d);
  const Comparison first = align_records(d, ds, m1);
  const Comparison fresh = align_records(d, ds, m2);
  ASSERT_EQ(first.alignment.rows.size(), d.rows.size());
  for (std::size_t v = 0; v < 2; ++v)
    for (std::size_t i = 0; i < d.rows.size(); ++i) {
      const double reused = aligned_value(first.alignment.rows[i], m2, v);
      ASSERT_TRUE(reused == fresh.alignment.model[v][i] ||
                  (std::isnan(reused) && std::isnan(fresh.alignment.model[v][i])))
          << "row " << i << " variable " << v;
    }
  // align_records is compare without the error groups: the same alignment.
  const Comparison full = compare(d, ds, m2);
  EXPECT_EQ(full.alignment.model[0], fresh.alignment.model[0]);
  EXPECT_TRUE(fresh.stages.empty());
  EXPECT_FALSE(full.stages.empty());
}

TEST(Compare, TheNormalStressRuleIsTheOneCompareRefusesBy) {
  // Calibration checks a reused placement's normal stress with normal_stress_mismatch: the same
  // rule and words as compare's refusal (4 MPa measured; 1 % + 0.01 MPa allowed by default).
  const MeasurementFile d = make(path(40.0, 4.0), false, 0.0, 100, 1.0);
  const Segmentation ds = segment(d);
  const StageInfo& st = ds.stages[1];
  EXPECT_EQ(normal_stress_mismatch(st, 4.04), "");
  const std::string why = normal_stress_mismatch(st, 5.0);
  EXPECT_NE(why.find("stage 2: different normal stress"), std::string::npos) << why;
  const MeasurementFile m = make(path(40.0, 5.0), true, 0.5, 0, 1.0);
  try {
    compare(d, m);
    ADD_FAILURE() << "compare accepted 5 MPa against 4 MPa";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), why);
  }
}
