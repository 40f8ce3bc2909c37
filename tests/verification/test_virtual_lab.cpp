// Virtual lab: the behaviours the CNWRA report saw in the laboratory (sections 2.2, 2.3) must
// emerge from the twins' mechanics (rough walls, facet friction, crushing and wear), not be put
// in. Each test runs the twin generator in-process on its case file in cases/virtual_lab/ and
// measures the behaviour on the record; the wear-free controls show the measures fail without
// the mechanics.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>

#include "framework/lab/virtual_lab/twin.hpp"

using namespace rockdem;
using namespace rockdem::vlab;

namespace {

std::string case_path(const std::string& nn) {
  return std::string(ROCKDEM_SOURCE_DIR) + "/cases/virtual_lab/test" + nn + ".toml";
}

std::vector<MeasurementRow> stage_rows(const MeasurementFile& f, int stage) {
  std::vector<MeasurementRow> out;
  for (const auto& r : f.rows)
    if (r.stage == stage) out.push_back(r);
  return out;
}

// A one-sided stage (0 -> +A -> 0) split at its largest shear displacement.
struct Strokes {
  std::vector<MeasurementRow> forward, reverse;
};
Strokes split(const std::vector<MeasurementRow>& rows) {
  std::size_t turn = 0;
  for (std::size_t i = 0; i < rows.size(); ++i)
    if (rows[i].shear_disp_mm > rows[turn].shear_disp_mm) turn = i;
  Strokes s;
  s.forward.assign(rows.begin(), rows.begin() + static_cast<long>(turn) + 1);
  s.reverse.assign(rows.begin() + static_cast<long>(turn), rows.end());
  return s;
}

double mean_of(const std::vector<MeasurementRow>& rows, double u_lo, double u_hi,
               const std::function<double(const MeasurementRow&)>& value) {
  double sum = 0.0;
  int n = 0;
  for (const auto& r : rows)
    if (r.shear_disp_mm >= u_lo && r.shear_disp_mm <= u_hi) {
      sum += value(r);
      ++n;
    }
  return n > 0 ? sum / n : std::nan("");
}

// Normal displacement at shear displacement u on a stroke (linear between rows).
double dilation_at(const std::vector<MeasurementRow>& rows, double u) {
  for (std::size_t i = 1; i < rows.size(); ++i) {
    const double a = rows[i - 1].shear_disp_mm, b = rows[i].shear_disp_mm;
    if ((u - a) * (u - b) <= 0.0 && a != b) {
      const double f = (u - a) / (b - a);
      return rows[i - 1].normal_disp_mm + f * (rows[i].normal_disp_mm - rows[i - 1].normal_disp_mm);
    }
  }
  return std::nan("");
}

// Harmonic test: rows of cycle c (1-based) and quadrant q as numbered in the report (1: away on
// the + side, 4: back from +, 3: away on the - side, 2: back from -), from the drive's phase.
std::vector<MeasurementRow> quadrant(const MeasurementFile& f, double period, int cycle, int q) {
  static constexpr int order[4] = {1, 4, 3, 2};
  std::vector<MeasurementRow> out;
  for (const auto& r : f.rows) {
    const double phase = r.time_s / period - (cycle - 1);
    if (phase < 0.0 || phase >= 1.0) continue;
    if (order[std::min(3, static_cast<int>(phase * 4.0))] == q) out.push_back(r);
  }
  return out;
}

double max_dilation(const std::vector<MeasurementRow>& rows) {
  double m = -1e9;
  for (const auto& r : rows) m = std::max(m, r.normal_disp_mm);
  return m;
}

}  // namespace

// (a) Reverse shearing is weaker than the end of forward shearing (report 2.2, Figure 2-1): on
// the way back the top block slides down the facets it climbed, and on worn ones.
TEST(VirtualLab, ReverseShearStrengthIsBelowTheEndOfForwardShearing) {
  const TwinRun run = run_twin(read_twin_case(case_path("09")));
  for (int stage = 1; stage <= 3; ++stage) {
    const Strokes s = split(stage_rows(run.record, stage));
    const double fwd_end = mean_of(s.forward, 30.0, 40.0, [](const MeasurementRow& r) { return r.shear_stress_MPa; });
    const double rev = mean_of(s.reverse, 5.0, 35.0, [](const MeasurementRow& r) { return -r.shear_stress_MPa; });
    std::printf("test09 stage %d: forward 30-40 mm %.3f MPa, reverse 35-5 mm %.3f MPa (ratio %.3f)\n", stage, fwd_end,
                rev, rev / fwd_end);
    EXPECT_GT(rev, 0.0);
    EXPECT_LT(rev, 0.92 * fwd_end) << "stage " << stage;
  }
}

// (b) Dilation recovers on reverse shearing, the return curve below the forward one (report 2.2,
// Figure 2-2): the geometry is reversible, the worn and crushed material is not.
TEST(VirtualLab, DilationRecoversOnReverseShearingWithHysteresis) {
  const TwinRun run = run_twin(read_twin_case(case_path("09")));
  for (int stage = 1; stage <= 3; ++stage) {
    const auto rows = stage_rows(run.record, stage);
    const Strokes s = split(rows);
    const double dmax = max_dilation(rows), dend = rows.back().normal_disp_mm;
    double gap = 0.0;
    int n = 0;
    for (double u = 5.0; u <= 35.0; u += 1.0, ++n) gap += dilation_at(s.forward, u) - dilation_at(s.reverse, u);
    gap /= n;
    std::printf("test09 stage %d: max dilation %.3f mm, at the end %.3f mm, forward minus reverse (5-35 mm) %.3f mm\n",
                stage, dmax, dend, gap);
    EXPECT_LT(std::abs(dend), 0.15 * dmax) << "stage " << stage;
    EXPECT_GT(gap, 0.03 * dmax) << "stage " << stage;
  }
}

// Mean |shear stress| over the part of a quadrant where 2 mm <= |u| <= 12 mm (past the elastic
// turn-around, short of the amplitude).
double quadrant_level(const MeasurementFile& f, double period, int cycle, int q) {
  double sum = 0.0;
  int n = 0;
  for (const auto& r : quadrant(f, period, cycle, q))
    if (std::abs(r.shear_disp_mm) >= 2.0 && std::abs(r.shear_disp_mm) <= 12.0) {
      sum += std::abs(r.shear_stress_MPa);
      ++n;
    }
  return n > 0 ? sum / n : std::nan("");
}

// (c) Harmonic test, first cycle: a second peak in the third quadrant, where the top block first
// meets the surface beyond the mated position on the other side (fresh facets; report 2.3 and
// Figure 5-38): as strong as the first quadrant of cycle 1, stronger than the third quadrant of
// cycle 2 and than the already worn first quadrant of cycle 2. (d) Wear continues over the 40
// cycles (report Figures 2-3, 2-7): strength and dilation of cycle 40 below those of cycle 1.
TEST(VirtualLab, HarmonicTestFreshSurfacePeakAndWearOverFortyCycles) {
  const TwinCase c = read_twin_case(case_path("14"));
  const double period = 1.0 / c.stages.front().path.frequency;
  const TwinRun run = run_twin(c);
  const auto& f = run.record;
  const double q1_c1 = quadrant_level(f, period, 1, 1), q4_c1 = quadrant_level(f, period, 1, 4);
  const double q3_c1 = quadrant_level(f, period, 1, 3), q1_c2 = quadrant_level(f, period, 2, 1);
  const double q3_c2 = quadrant_level(f, period, 2, 3), q1_c40 = quadrant_level(f, period, 40, 1);
  auto cycle_dilation = [&](int k) {
    double m = -1e9;
    for (int q = 1; q <= 4; ++q) m = std::max(m, max_dilation(quadrant(f, period, k, q)));
    return m;
  };
  const double dil_c1 = cycle_dilation(1), dil_c40 = cycle_dilation(40);
  std::printf("test14 mean |tau| (2-12 mm): cycle 1 q1 %.3f q4 %.3f q3 %.3f; cycle 2 q1 %.3f q3 %.3f; cycle 40 q1 %.3f MPa; "
              "max dilation cycle 1 %.3f, cycle 40 %.3f mm\n",
              q1_c1, q4_c1, q3_c1, q1_c2, q3_c2, q1_c40, dil_c1, dil_c40);
  EXPECT_GT(q3_c1, 0.9 * q1_c1);   // the second peak, as high as the first
  EXPECT_GT(q3_c1, 2.0 * q4_c1);   // not the reverse-shearing level
  EXPECT_GT(q3_c1, 1.15 * q3_c2);  // met fresh only once
  EXPECT_GT(q3_c1, 1.15 * q1_c2);  // the positive side is worn by then
  EXPECT_LT(q1_c40, 0.85 * q1_c1);
  EXPECT_LT(dil_c40, 0.8 * dil_c1);

  // Control: without wear and crushing the surfaces never change, so cycle 2 repeats cycle 1;
  // the fresh-surface and wear measures above then fail.
  TwinCase unworn = c;
  unworn.settings.wear_coefficient = 0.0;
  unworn.settings.wall_strength = 1e15;
  unworn.settings.noise_stress = unworn.settings.noise_shear_disp = unworn.settings.noise_normal_disp = 0.0;
  unworn.stages.front().path.count = 3;
  const TwinRun control = run_twin(unworn);
  const double u3_c1 = quadrant_level(control.record, period, 1, 3), u3_c2 = quadrant_level(control.record, period, 2, 3);
  const double u1_c2 = quadrant_level(control.record, period, 2, 1), u1_c3 = quadrant_level(control.record, period, 3, 1);
  std::printf("unworn control: q3 cycle 1 %.3f, cycle 2 %.3f; q1 cycle 2 %.3f, cycle 3 %.3f MPa\n", u3_c1, u3_c2, u1_c2,
              u1_c3);
  EXPECT_LT(u3_c1, 1.15 * u3_c2);
  EXPECT_GT(u1_c3, 0.85 * u1_c2);
}

// (e) Less dilation at higher normal stress (report 2.2): across the stages of test 11 on one
// specimen, and on two fresh specimens of test 9 sheared once each at 3 and at 5 MPa (so that
// it is not only the wear of the earlier stages).
TEST(VirtualLab, LessDilationAtHigherNormalStress) {
  const TwinRun run = run_twin(read_twin_case(case_path("11")));
  double previous = 1e9;
  for (int stage = 1; stage <= 5; ++stage) {
    const double d = max_dilation(stage_rows(run.record, stage));
    std::printf("test11 stage %d: max dilation %.3f mm\n", stage, d);
    EXPECT_LT(d, previous) << "stage " << stage;
    previous = d;
  }
  TwinCase one = read_twin_case(case_path("09"));
  one.stages.resize(1);
  one.stages.front().normal_stress = 3e6;
  const double d3 = max_dilation(run_twin(one).record.rows);
  one.stages.front().normal_stress = 5e6;
  const double d5 = max_dilation(run_twin(one).record.rows);
  std::printf("test09 fresh specimens: max dilation %.3f mm at 3 MPa, %.3f mm at 5 MPa\n", d3, d5);
  EXPECT_LT(d5, 0.96 * d3);
  // Control: rigid asperities that neither crush nor wear ride over the same heights whatever
  // the normal stress.
  one.settings.wear_coefficient = 0.0;
  one.settings.wall_strength = 1e15;
  one.settings.contact_stiffness = 1e16;
  one.settings.noise_normal_disp = 0.0;
  const double r5 = max_dilation(run_twin(one).record.rows);
  one.stages.front().normal_stress = 3e6;
  const double r3 = max_dilation(run_twin(one).record.rows);
  std::printf("rigid control: max dilation %.4f mm at 3 MPa, %.4f mm at 5 MPa\n", r3, r5);
  EXPECT_GT(r5, 0.99 * r3);
}

// The generator is reproducible bit for bit for a seed, and another seed makes another twin.
TEST(VirtualLab, TwinsAreReproducibleForASeed) {
  const TwinCase c = read_twin_case(case_path("07"));
  const TwinRun a = run_twin(c), b = run_twin(c), other = run_twin(c, 1234);
  ASSERT_EQ(a.record.rows.size(), b.record.rows.size());
  for (std::size_t i = 0; i < a.record.rows.size(); ++i) {
    ASSERT_EQ(a.record.rows[i].shear_stress_MPa, b.record.rows[i].shear_stress_MPa) << i;
    ASSERT_EQ(a.record.rows[i].normal_disp_mm, b.record.rows[i].normal_disp_mm) << i;
  }
  bool differs = false;
  for (std::size_t i = 0; i < std::min(a.record.rows.size(), other.record.rows.size()); ++i)
    differs = differs || a.record.rows[i].shear_stress_MPa != other.record.rows[i].shear_stress_MPa;
  EXPECT_TRUE(differs);
  bool synthetic = false;
  for (const auto& [k, v] : a.record.metadata) synthetic = synthetic || (k == "source" && v == "synthetic");
  EXPECT_TRUE(synthetic);
}
