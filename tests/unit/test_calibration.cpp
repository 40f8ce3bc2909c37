// Calibration: known parameters recovered from element-driver records with seeded noise (within
// a few standard errors and a few per cent), fixed parameters stay fixed, bounds are respected
// and flagged, starting-value estimates are close on clean data, unknown names are InputErrors.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <numbers>
#include <random>

#include "tests/unit/noisy_record.hpp"
#include "framework/analysis/calibration.hpp"
#include "framework/analysis/calibration_fit.hpp"
#include "framework/analysis/segmentation.hpp"
#include "framework/core/error.hpp"
#include "framework/io/measurement_csv.hpp"
#include "framework/plugin_api/joint_law.hpp"

using namespace rockdem;

namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

RawValue q(const char* text) { return RawValue{std::string(text), "test"}; }

// The test records: one-sided strokes, increments of 0.025 mm, every 4th kept (noisy_record.hpp).
MeasurementFile record(const std::string& law, const RawValues& p, unsigned seed, double noise = 1.0) {
  auto model = make_joint_model(law, p, {}, "test");
  return testutil::noisy_two_stage_record(*model, 2.5e-5, 4, true, seed, noise);
}

CalibrationOptions options(const std::string& law) {
  CalibrationOptions o;
  o.law = law;
  o.element.max_step = 2.5e-5;
  o.element.length = 0.2;
  o.fit_step = 5e-5;
  return o;
}

const FittedParam& param(const CalibrationResult& r, const std::string& n) {
  for (const auto& p : r.params)
    if (p.name == n) return p;
  throw std::runtime_error("no parameter " + n);
}

// |fitted - true| within 4 standard errors or 3 % of the true value, whichever is larger.
void expect_recovered(const CalibrationResult& r, const std::string& n, double truth) {
  const FittedParam& p = param(r, n);
  EXPECT_TRUE(p.free) << n;
  EXPECT_TRUE(std::isfinite(p.se)) << n;
  EXPECT_LE(std::abs(p.value - truth), std::max(4.0 * p.se, 0.03 * std::abs(truth)))
      << n << ": fitted " << p.value << " +- " << p.se << ", true " << truth;
}

// Fits `law` (dilation reversible, as the record was made) to a noisy record of `truth`.
CalibrationResult fit(const std::string& law, const RawValues& truth, unsigned seed) {
  const MeasurementFile f = record(law, truth, seed);
  CalibrationOptions o = options(law);
  o.law_values["dilation"] = q("reversible");
  return calibrate(f, segment(f), o);
}

const RawValues kMc{{"kn", q("40 GPa/m")},       {"ks", q("12 GPa/m")}, {"friction", q("36 deg")},
                    {"dilation_angle", q("5 deg")}, {"dilation", q("reversible")}};
const RawValues kCy{{"kn", q("40 GPa/m")},         {"ks", q("15 GPa/m")},       {"initial_friction", q("50 deg")},
                    {"friction", q("32 deg")},     {"roughness", q("3 mm")},    {"dilation", q("reversible")}};

}  // namespace

TEST(Calibration, StartingEstimatesCloseOnCleanData) {
  const MeasurementFile f = record("mohr_coulomb", kMc, 1, 0.0);
  const Segmentation seg = segment(f);
  const DataEstimates e = estimate_from_data(f, seg);
  EXPECT_NEAR(e.ks, 12e9, 0.1 * 12e9);
  EXPECT_NEAR(e.peak_friction, 36 * kDeg, 0.5 * kDeg);
  EXPECT_NEAR(e.residual_friction, 36 * kDeg, 0.5 * kDeg);
  EXPECT_NEAR(e.dilation_angle, 5 * kDeg, 0.3 * kDeg);
  EXPECT_NEAR(e.mean_normal_stress, 3e6, 1e3);
}

TEST(Calibration, RecoversMohrCoulombFromNoisyRecord) {
  const CalibrationResult r = fit("mohr_coulomb", kMc, 7);
  EXPECT_TRUE(r.converged) << r.status;
  expect_recovered(r, "ks", 12e9);
  expect_recovered(r, "friction", 36 * kDeg);
  expect_recovered(r, "dilation_angle", 5 * kDeg);
  EXPECT_EQ(r.k, 3);
  EXPECT_LT(r.nrmse[2], 0.01);
  // The fitting step changes the answer by less than 1 %.
  EXPECT_NEAR(r.nrmse_fit[2], r.nrmse[2], 0.01 * r.nrmse[2]);
}

TEST(Calibration, RecoversContinuouslyYieldingFromNoisyRecord) {
  const CalibrationResult r = fit("continuously_yielding", kCy, 11);
  EXPECT_TRUE(r.converged) << r.status;
  expect_recovered(r, "initial_friction", 50 * kDeg);
  expect_recovered(r, "friction", 32 * kDeg);
  expect_recovered(r, "roughness", 3e-3);
  expect_recovered(r, "ks", 15e9);
  EXPECT_LT(r.nrmse[2], 0.01);
}

TEST(Calibration, FixedParametersStayFixedAndBoundsAreRespected) {
  const MeasurementFile f = record("mohr_coulomb", kMc, 3);
  const Segmentation seg = segment(f);
  CalibrationOptions o = options("mohr_coulomb");
  o.law_values["dilation"] = q("reversible");
  o.fix_text["friction"] = "30 deg";  // wrong on purpose: the others adapt, it stays
  o.fix["ks"] = 12e9;
  const CalibrationResult r = calibrate(f, seg, o);
  EXPECT_FALSE(param(r, "friction").free);
  EXPECT_DOUBLE_EQ(param(r, "friction").value, 30 * kDeg);
  EXPECT_DOUBLE_EQ(param(r, "ks").value, 12e9);
  EXPECT_EQ(r.k, 1);
  for (const auto& p : r.params) {
    if (!p.free) continue;
    EXPECT_GE(p.value, p.lower) << p.name;
    EXPECT_LE(p.value, p.upper) << p.name;
  }
  // Data without dilation: the dilation angle ends at its lower bound (0) and says so.
  RawValues flat = kMc;
  flat["dilation_angle"] = q("0 deg");
  const MeasurementFile g = record("mohr_coulomb", flat, 5);
  const CalibrationResult rb = calibrate(g, segment(g), options("mohr_coulomb"));
  EXPECT_TRUE(param(rb, "dilation_angle").at_bound) << param(rb, "dilation_angle").value << " " << rb.status;
  EXPECT_GE(param(rb, "dilation_angle").value, 0.0);
  bool warned = false;
  for (const auto& w : rb.warnings) warned = warned || w.find("dilation_angle is at its lower bound") != std::string::npos;
  EXPECT_TRUE(warned);
}

// The fitted model's run counts its increments and those that missed the stage's normal
// condition (JSON `increments`, `missed_increments`; a warning when any). Mohr-Coulomb with
// dilation_recovery and rate_and_state on the first reversals of test 14's twin missed 3,039 of
// 15,991 before rate_and_state's strength was evaluated at the final normal stress
// (2026-11-28): the regularised creep just after a reversal, carried as a factor, left no
// consistent normal stress, and the joint lifted off. Now it misses none, as the law alone.
TEST(Calibration, IncrementsThatMissTheNormalConditionAreCounted) {
  MeasurementFile f = read_measurement_csv(std::string(ROCKDEM_SOURCE_DIR) + "/cases/direct_shear/twins/test14.csv");
  f.rows.resize(300);  // the first stroke and the first reversals, to 0.3 s
  const Segmentation seg = segment(f);
  CalibrationOptions o;
  o.law = "mohr_coulomb";
  o.element.max_step = 1e-5;
  o.element.length = 0.2032;
  for (const auto& [name, value] : std::map<std::string, std::string>{
           {"kn", "200 GPa/m"}, {"ks", "10 GPa/m"}, {"friction", "40 deg"}, {"dilation_angle", "10 deg"}})
    o.fix_text[name] = value;
  const CalibrationResult plain = calibrate(f, seg, o);
  EXPECT_GT(plain.increments, static_cast<long>(f.rows.size()));
  EXPECT_EQ(plain.missed_increments, 0);

  o.effects = {"dilation_recovery", "rate_and_state"};
  for (const auto& [name, value] : std::map<std::string, std::string>{{"dilation_recovery.residual_fraction", "0"},
                                                                       {"dilation_recovery.hysteresis", "1"},
                                                                       {"rate_and_state.a", "0.01"},
                                                                       {"rate_and_state.b", "0.015"},
                                                                       {"rate_and_state.critical_slip", "20 um"}})
    o.fix_text[name] = value;
  const CalibrationResult r = calibrate(f, seg, o);
  EXPECT_GT(r.increments, static_cast<long>(f.rows.size()));
  EXPECT_EQ(r.missed_increments, 0);
  for (const auto& w : r.warnings) EXPECT_EQ(w.find("missed the stage's normal condition"), std::string::npos) << w;
  const nlohmann::json j = to_json(r);
  EXPECT_EQ(j.at("missed_increments").get<long>(), r.missed_increments);
  EXPECT_EQ(j.at("increments").get<long>(), r.increments);
}

// Continuously-Yielding's roughness sets both how fast the stress softens and how long the joint
// dilates. On test 9's twin (a virtual-lab record) the stress softens within a few millimetres
// while the dilation goes on over the 40 mm stroke; started from the softening estimate (a few
// mm) the fit stayed where the joint stops dilating early (roughness 7 mm, combined NRMSE 0.249,
// normal displacement 0.46). The start's decade scan finds the basin of a roughness of some 0.5 m.
TEST(Calibration, ContinuouslyYieldingFindsTheRoughnessTheDilationNeeds) {
  const MeasurementFile f = read_measurement_csv(std::string(ROCKDEM_SOURCE_DIR) + "/cases/direct_shear/twins/test09.csv");
  CalibrationOptions o;
  o.law = "continuously_yielding";
  o.element.length = 0.2032;
  o.law_values["dilation"] = q("reversible");
  const CalibrationResult r = calibrate(f, segment(f), o);
  EXPECT_LT(r.nrmse[2], 0.07);
  EXPECT_LT(r.nrmse[1], 0.1);
  EXPECT_GT(param(r, "roughness").value, 0.1);
  // The scan moved the start up by a decade or more from the softening estimate.
  const Segmentation seg = segment(f);
  const double estimate = estimate_from_data(f, seg).softening_disp / std::numbers::ln2;
  EXPECT_GE(param(r, "roughness").start, 9.9 * estimate) << estimate;
  // A roughness the user gives is a start the scan leaves alone.
  o.law_values["roughness"] = q("7 mm");
  o.law_values["kn"] = q("180 GPa/m");
  const CalibrationResult given = calibrate(f, segment(f), o);
  EXPECT_DOUBLE_EQ(param(given, "roughness").start, 7e-3);
}

TEST(Calibration, UnknownNamesAreInputErrorsListingTheValidOnes) {
  const MeasurementFile f = record("mohr_coulomb", kMc, 2);
  const Segmentation seg = segment(f);
  CalibrationOptions o = options("mohr_coulomb");
  o.fix["bogus"] = 1.0;
  try {
    calibrate(f, seg, o);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("unknown parameter 'bogus'"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("dilation_angle"), std::string::npos) << e.what();
  }
  CalibrationOptions o2 = options("no_such_law");
  EXPECT_THROW(calibrate(f, seg, o2), InputError);
  CalibrationOptions o3 = options("mohr_coulomb");
  o3.fix_text["friction"] = "30";  // an angle needs its unit
  EXPECT_THROW(calibrate(f, seg, o3), InputError);
}

TEST(Calibration, AReusedPlacementGivesTheResidualsAndJacobianOfAFreshEvaluator) {
  // A fit's Evaluator keeps where the measured rows sit on the model record of each driver step
  // and reuses it while the record's path columns are the same to the bit (calibration_fit.hpp,
  // Placement). Its residuals and forward-difference Jacobian (columns on two threads) must be
  // those of an Evaluator that aligns every run afresh, to the bit, at both steps.
  using calibration_detail::Evaluator;
  using calibration_detail::Slot;
  const RawValues mc{{"kn", q("40 GPa/m")},          {"ks", q("15 GPa/m")},
                     {"friction", q("35 deg")},      {"dilation_angle", q("5 deg")},
                     {"dilation", q("reversible")}};
  auto model = make_joint_model("mohr_coulomb", mc, {}, "test");
  const MeasurementFile f = testutil::noisy_two_stage_record(*model, 2.5e-5, 4, false, 7);
  const Segmentation seg = segment(f);
  CalibrationOptions o = options("mohr_coulomb");
  o.law_values = mc;
  o.threads = 2;
  auto slot = [](const char* name, Dimension dim, double lo, double hi) {
    Slot s;
    s.info.name = name;
    s.info.kind = "real";
    s.info.dim = dim;
    s.name = name;
    s.owner = "mohr_coulomb";
    s.free = true;
    s.lower = lo;
    s.upper = hi;
    s.value = s.start = 0.5 * (lo + hi);
    return s;
  };
  const double deg = std::numbers::pi / 180.0;
  const std::vector<Slot> slots{slot("friction", Dimension::angle, 25 * deg, 45 * deg),
                                slot("ks", Dimension::stiffness, 5e9, 3e10),
                                slot("dilation_angle", Dimension::angle, 0.0, 10 * deg)};
  const std::vector<std::size_t> free{0, 1, 2};
  const std::vector<ElementStage> stages = stages_from_data(f, seg);
  const Evaluator warm(f, seg, o, slots, free, stages);
  const std::vector<std::vector<double>> points{{0.5, 0.4, 0.5}, {0.2, 0.9, 0.1}, {0.8, 0.1, 0.9}, {0.5, 0.4, 0.5}};
  for (const double step : {5e-5, 2.5e-5}) {
    for (const auto& x : points) {
      const Evaluator fresh(f, seg, o, slots, free, stages);
      std::vector<double> rw, rf;
      ASSERT_TRUE(warm.residuals(x.data(), step, rw));
      ASSERT_TRUE(fresh.residuals(x.data(), step, rf));
      ASSERT_EQ(rw.size(), rf.size());
      for (std::size_t i = 0; i < rw.size(); ++i) ASSERT_EQ(rw[i], rf[i]) << "residual " << i << " step " << step;
      Eigen::MatrixXd jw, jf;
      ASSERT_TRUE(warm.jacobian(x.data(), rw, step, jw));
      ASSERT_TRUE(fresh.jacobian(x.data(), rf, step, jf));
      EXPECT_TRUE(jw == jf) << "step " << step;
    }
  }
  // The warm one did reuse its placements (every run after the first at each step, its
  // Jacobian's included); the fresh ones only within their Jacobians.
  EXPECT_GE(warm.placement_hits(), 2 * (static_cast<long>(points.size()) * 4 - 1));
}

// A refit of a fitted model with more parameters free (diagnose's rung refit) starts where the
// fit ended, a value on its bound kept there: moved inside its bounds, as a cold start is, the
// refit of test 9's twin's rung 2 started from an objective 6 % above the fit's and ended above
// it (combined NRMSE 0.0589 against 0.0579).
TEST(Calibration, ARefitFromAnOptimumStartsOnItsBounds) {
  RawValues flat = kMc;
  flat["dilation_angle"] = q("0 deg");
  const MeasurementFile g = record("mohr_coulomb", flat, 5);
  const Segmentation seg = segment(g);
  const CalibrationResult first = calibrate(g, seg, options("mohr_coulomb"));
  ASSERT_TRUE(param(first, "dilation_angle").at_bound);
  CalibrationOptions o = options("mohr_coulomb");
  for (const auto& p : first.params)
    if (p.free) o.start[p.name] = p.value;
  CalibrationOptions moved = o;
  o.start_is_optimum = true;
  const CalibrationResult again = calibrate(g, seg, o);
  EXPECT_DOUBLE_EQ(param(again, "dilation_angle").start, param(first, "dilation_angle").value);
  EXPECT_LE(again.rss, first.rss * (1.0 + 1e-9));
  // Without the flag the same start is moved inside the bounds.
  const CalibrationResult cold = calibrate(g, seg, moved);
  EXPECT_GT(param(cold, "dilation_angle").start, param(first, "dilation_angle").value);
}

// CalibrationOptions::other_starts: the fit starts from the point of the lowest objective, its
// own start included (one run each at the fitting step).
TEST(Calibration, TheFitStartsFromTheBestOfItsOtherStarts) {
  const MeasurementFile f = record("mohr_coulomb", kMc, 3);
  const Segmentation seg = segment(f);
  CalibrationOptions o = options("mohr_coulomb");
  o.law_values["dilation"] = q("reversible");
  o.start["friction"] = 20 * kDeg;
  o.other_starts = {{{"friction", 10 * kDeg}}, {{"friction", 35 * kDeg}}, {{"no_such_parameter", 1.0}}};
  const CalibrationResult better = calibrate(f, seg, o);
  EXPECT_NEAR(param(better, "friction").start, 35 * kDeg, 1e-12);
  o.other_starts = {{{"friction", 10 * kDeg}}};
  const CalibrationResult worse = calibrate(f, seg, o);
  EXPECT_NEAR(param(worse, "friction").start, 20 * kDeg, 1e-12);
  EXPECT_NEAR(param(better, "friction").value, 36 * kDeg, 1 * kDeg);
}

// Profile-likelihood intervals (calibration_profile.cpp): by default for the parameters whose
// standard error says little. On a record without dilation the dilation angle ends on its lower
// bound: its interval is open there (the record cannot tell 0 from a little) and closed above,
// and it holds the true value. Asked for every parameter, the friction angle's holds its true
// value too and brackets the fitted one.
TEST(Calibration, ProfileIntervalsWhereTheStandardErrorSaysLittle) {
  RawValues flat = kMc;
  flat["dilation_angle"] = q("0 deg");
  const MeasurementFile g = record("mohr_coulomb", flat, 5);
  const Segmentation seg = segment(g);
  CalibrationOptions o = options("mohr_coulomb");
  o.law_values["dilation"] = q("reversible");
  const CalibrationResult r = calibrate(g, seg, o);
  const FittedParam& dil = param(r, "dilation_angle");
  ASSERT_TRUE(dil.at_bound);
  ASSERT_TRUE(dil.profiled());
  EXPECT_TRUE(dil.profile_lower_open);
  EXPECT_EQ(dil.profile_lower, dil.lower);
  EXPECT_FALSE(dil.profile_upper_open);
  EXPECT_GT(dil.profile_upper, dil.value);
  EXPECT_LT(dil.profile_upper, 2 * kDeg) << "a record of 0 deg cannot allow a large dilation angle";
  EXPECT_GT(dil.profile_fits, 2);
  EXPECT_FALSE(param(r, "friction").profiled()) << "well determined: not profiled by default";
  bool warned = false;
  for (const auto& w : r.warnings) warned = warned || w.find("dilation_angle is not pinned down below") != std::string::npos;
  EXPECT_TRUE(warned);

  o.profile = CalibrationOptions::Profile::all;
  const CalibrationResult all = calibrate(g, seg, o);
  const FittedParam& fr = param(all, "friction");
  ASSERT_TRUE(fr.profiled());
  EXPECT_FALSE(fr.profile_lower_open);
  EXPECT_FALSE(fr.profile_upper_open);
  EXPECT_LT(fr.profile_lower, fr.value);
  EXPECT_GT(fr.profile_upper, fr.value);
  EXPECT_LE(fr.profile_lower, 36 * kDeg);
  EXPECT_GE(fr.profile_upper, 36 * kDeg);

  o.profile = CalibrationOptions::Profile::none;
  const CalibrationResult none = calibrate(g, seg, o);
  for (const auto& p : none.params) EXPECT_FALSE(p.profiled()) << p.name;
}
