// Diagnosis: covariate scores on synthetic residuals with a known dependence, the effects that a
// record cannot reveal, the IC ladder stopping when nothing helps, the JSON keys of the issue,
// and a blind test: an effect drawn at random from the catalogue (seeded per run, logged) with
// parameters unlike its defaults, data from the composed law plus noise; diagnose, not told, must
// rank it first and cut the combined NRMSE substantially.
#include <algorithm>
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <cstdio>
#include <random>

#include "tests/unit/noisy_record.hpp"
#include "framework/analysis/diagnosis.hpp"
#include "framework/plugin_api/joint_law.hpp"

using namespace rockdem;

namespace {

RawValue q(const char* text) { return RawValue{std::string(text), "test"}; }

const RawValues kMc{{"kn", q("40 GPa/m")},       {"ks", q("12 GPa/m")},        {"friction", q("36 deg")},
                    {"dilation_angle", q("4 deg")}, {"dilation", q("reversible")}};

// Mohr-Coulomb records, increments of 0.0125 mm, every 8th kept (noisy_record.hpp).
MeasurementFile record(const RawValues& law, const std::vector<EffectSpec>& effects, bool one_sided, unsigned seed) {
  auto model = make_joint_model("mohr_coulomb", law, effects, "test");
  return testutil::noisy_two_stage_record(*model, 1.25e-5, 8, one_sided, seed);
}

DiagnosisOptions options(const std::vector<std::string>& effects) {
  DiagnosisOptions o;
  o.base.law = "mohr_coulomb";
  o.base.law_values["dilation"] = q("reversible");
  o.base.law_values["kn"] = q("40 GPa/m");  // fixed by default: measured in a normal loading test
  o.base.element.max_step = 1.25e-5;
  o.base.element.length = 0.2;
  // The fitting step equal to the record's: MC with monotonic dilation + dilation_recovery changes by
  // more than the 1 % at a coarser step (the reversal transient), which is not what this tests.
  o.base.fit_step = 1.25e-5;
  o.effects = effects;
  // These tests judge the effects on the base law that made the record; the base-law check (nine
  // more fits per diagnosis) has its own test below.
  o.check_base_laws = false;
  return o;
}

}  // namespace

TEST(Diagnosis, CovariateScoresFindAKnownDependence) {
  const MeasurementFile f = record(kMc, {}, false, 1);
  const Segmentation seg = segment(f);
  const Covariates c = row_covariates(f, seg);
  ASSERT_EQ(c.names.size(), 8u);
  std::mt19937 rng(4);
  std::normal_distribution<double> g(0.0, 0.01);
  std::array<std::vector<double>, 2> r;
  for (std::size_t i = 0; i < f.rows.size(); ++i) {
    // Shear stress: too strong when shearing back toward the origin; normal displacement: an
    // error growing with the offset.
    r[0].push_back((seg.labels[i].direction < 0 ? 0.1 : 0.0) + g(rng));
    r[1].push_back(0.02 * std::abs(f.rows[i].shear_disp_mm) + g(rng));
  }
  const auto s = score_covariates(c, r);
  const CovariateScore* best_tau = nullptr;
  const CovariateScore* best_un = nullptr;
  for (const auto& x : s) {
    if (!best_tau && x.variable == "shear_stress") best_tau = &x;
    if (!best_un && x.variable == "normal_disp") best_un = &x;
  }
  ASSERT_TRUE(best_tau && best_un);
  EXPECT_EQ(best_tau->name, "toward_origin");
  EXPECT_GT(best_tau->score, 0.9);
  EXPECT_EQ(best_un->name, "offset");
  EXPECT_GT(best_un->score, 0.9);
  for (std::size_t i = 1; i < s.size(); ++i) EXPECT_GE(s[i - 1].score, s[i].score);
  // Pure noise explains nothing: every score near zero.
  for (auto& v : r[0]) v = g(rng);
  for (const auto& x : score_covariates(c, r)) {
    if (x.variable == "shear_stress") {
      EXPECT_LT(x.score, 0.02) << x.name;
    }
  }
}

TEST(Diagnosis, RecordsThatCannotRevealAnEffectSaySo) {
  const MeasurementFile one = record(kMc, {}, true, 2);
  const Segmentation s1 = segment(one);
  EXPECT_NE(unjudgeable_reason("directional_wear", one, s1).find("one side"), std::string::npos);
  EXPECT_NE(unjudgeable_reason("rate_and_state", one, s1).find("rate"), std::string::npos);
  EXPECT_NE(unjudgeable_reason("hyperbolic_normal_closure", one, s1).find("constant"), std::string::npos);
  EXPECT_EQ(unjudgeable_reason("reverse_shear_degradation", one, s1), "");
  // The first half of the first stroke only: no reverse shearing.
  MeasurementFile fwd = one;
  fwd.rows.resize(one.rows.size() / 8);
  const Segmentation s2 = segment(fwd);
  EXPECT_NE(unjudgeable_reason("reverse_shear_degradation", fwd, s2).find("no reverse shearing"), std::string::npos);
  EXPECT_NE(unjudgeable_reason("dilation_recovery", fwd, s2).find("no reverse shearing"), std::string::npos);
}

TEST(Diagnosis, LadderStopsWhenNothingHelpsAndJsonHasTheKeys) {
  // The base law itself made the data: no effect can pay for its parameters.
  const MeasurementFile f = record(kMc, {}, false, 3);
  const Segmentation seg = segment(f);
  DiagnosisOptions o = options({"reverse_shear_degradation", "dilation_recovery"});
  std::vector<std::string> progress;  // one line per fit as it finishes (stderr in the CLI)
  o.progress = [&](const std::string& line) { progress.push_back(line); };
  const Diagnosis d = diagnose(f, seg, o);
  ASSERT_EQ(d.ladder.size(), 1u) << format_report(d);
  for (const char* fit : {"] baseline mohr_coulomb: combined NRMSE ", "] effect reverse_shear_degradation alone: combined NRMSE ",
                          "] effect dilation_recovery alone: combined NRMSE "}) {
    const auto n = std::count_if(progress.begin(), progress.end(),
                                 [&](const std::string& l) { return l.front() == '[' && l.find(fit) != std::string::npos; });
    EXPECT_EQ(n, 1) << fit;
  }
  EXPECT_TRUE(d.ladder[0].effects.empty());
  for (const auto& t : d.ranking) {
    EXPECT_GT(t.delta_bic, 0.0) << t.effect;
    EXPECT_GT(t.delta_ic, 0.0) << t.effect;
  }
  // A record made by the law itself with white noise: its residuals are nearly independent.
  EXPECT_GT(d.baseline_size.total_n_eff(), 0.5 * static_cast<double>(d.baseline_size.total_n())) << format_report(d);
  const nlohmann::json j = to_json(d, "synthetic.csv");
  for (const char* k : {"data", "base_law", "baseline", "segments", "covariates", "ranking", "ladder", "ladder_decisions",
                        "final", "warnings"})
    EXPECT_TRUE(j.contains(k)) << k;
  for (const char* k : {"params", "nrmse"}) EXPECT_TRUE(j["baseline"].contains(k)) << k;
  for (const char* k : {"shear_stress", "normal_disp", "combined"}) EXPECT_TRUE(j["baseline"]["nrmse"].contains(k)) << k;
  ASSERT_FALSE(j["segments"].empty());
  for (const char* k : {"variable", "stage", "cycle", "quadrant", "n", "nrmse", "bias"})
    EXPECT_TRUE(j["segments"][0].contains(k)) << k;
  for (const char* k : {"variable", "name", "score"}) EXPECT_TRUE(j["covariates"][0].contains(k)) << k;
  for (const char* k : {"effect", "nrmse", "bic", "delta_bic", "delta_ic"}) EXPECT_TRUE(j["ranking"][0].contains(k)) << k;
  for (const char* k : {"effects", "nrmse", "bic", "effective_size"}) EXPECT_TRUE(j["ladder"][0].contains(k)) << k;
  for (const char* k : {"n", "n_eff", "shear_stress", "normal_disp"}) EXPECT_TRUE(j["baseline"]["effective_size"].contains(k)) << k;
  for (const char* k : {"n", "n_eff", "r1", "rss"}) EXPECT_TRUE(j["baseline"]["effective_size"]["shear_stress"].contains(k)) << k;
  EXPECT_TRUE(j.contains("rung_rule"));
  for (const char* k : {"effects", "params"}) EXPECT_TRUE(j["final"].contains(k)) << k;
}

// The ladder's rule: a rung must lower the IC (with the effective sizes of the chain it is added
// to) and the combined NRMSE the report shows; the decision says which failed, with the numbers.
// Shear stress only (500 residuals): a 10 % cut of its sum of squares with two more parameters
// pays when the residuals are independent (IC = BIC: 500 ln 0.9 + 2 ln 500 = -40.3) but not when
// they are worth 20 independent values (20 ln 0.9 + 2 ln 20 = +3.9): a shape missed over hundreds
// of rows is one misfit, not hundreds. The sizes weighing both fits are those the chain with the
// effect leaves (delta_ic).
TEST(Diagnosis, ARungMustLowerTheIcAndTheReportedError) {
  auto fit = [](double rss, int k, double combined) {
    CalibrationResult r;
    r.n = 500;
    r.rss = rss;
    r.k = k;
    r.bic = 500.0 * std::log(rss / 500.0) + k * std::log(500.0);
    r.nrmse = {combined, 0.0, combined};
    return r;
  };
  auto size = [](double rss, double n_eff) {
    EffectiveSize z;
    z.n = {500, 0};
    z.rss = {rss, 0.0};
    z.n_eff = {n_eff, 0.0};
    return z;
  };
  const CalibrationResult before = fit(10.0, 3, 0.105), halved = fit(5.0, 5, 0.065), tenth = fit(9.0, 5, 0.100),
                          error_up = fit(5.0, 5, 0.115);
  EXPECT_NEAR(information_criterion(size(10.0, 500.0), 3, size(10.0, 500.0)), before.bic, 1e-9);  // white: the BIC
  const LadderDecision a = judge_rung(1, "dilation_recovery", halved, size(5.0, 20.0), before, size(10.0, 20.0));
  EXPECT_TRUE(a.added) << a.reason;
  EXPECT_NEAR(a.delta_ic, 20.0 * std::log(0.5) + 2.0 * std::log(20.0), 1e-9);
  EXPECT_NEAR(a.delta_bic, 500.0 * std::log(0.5) + 2.0 * std::log(500.0), 1e-9);
  EXPECT_NE(a.reason.find("from 0.1050 to 0.0650"), std::string::npos) << a.reason;
  const LadderDecision b = judge_rung(1, "rate_and_state", tenth, size(9.0, 500.0), before, size(10.0, 500.0));
  EXPECT_TRUE(b.added) << b.reason;
  EXPECT_NEAR(b.delta_ic, -40.3, 0.1);
  const LadderDecision c = judge_rung(1, "rate_and_state", tenth, size(9.0, 20.0), before, size(10.0, 20.0));
  EXPECT_FALSE(c.added);
  EXPECT_NEAR(c.delta_ic, 3.9, 0.1);
  EXPECT_LT(c.delta_bic, 0.0);
  EXPECT_NE(c.reason.find("does not lower the IC (+3.9 with n_eff = 20 of 500 residuals)"), std::string::npos) << c.reason;
  const LadderDecision e = judge_rung(2, "two_order_roughness", error_up, size(5.0, 20.0), before, size(10.0, 20.0));
  EXPECT_FALSE(e.added);
  EXPECT_NE(e.reason.find("raises the combined NRMSE from 0.1050 to 0.1150: not added"), std::string::npos) << e.reason;
  // An IC that falls (here by the parameters' penalty, none added) with an error that moves only in
  // its last digits: no rung.
  const CalibrationResult same = fit(10.0 * (1.0 - 1e-9), 3, 0.105 * (1.0 - 1e-9));
  const LadderDecision unchanged = judge_rung(1, "directional_wear", same, size(10.0 * (1.0 - 1e-9), 20.0), before, size(10.0, 20.0));
  EXPECT_LT(unchanged.delta_ic, 0.0);
  EXPECT_FALSE(unchanged.added) << unchanged.reason;
  EXPECT_NE(unchanged.reason.find("by less than 0.1 %"), std::string::npos) << unchanged.reason;
  const CalibrationResult small = fit(9.9, 3, 0.105 * (1.0 - 2e-3));  // 0.2 %: a cut
  EXPECT_TRUE(judge_rung(1, "directional_wear", small, size(9.9, 20.0), before, size(10.0, 20.0)).added);
  // Two variables: shear stress cut 25-fold (its residuals worth 20), normal displacement all noise
  // (rss 30 over 500 white residuals, unchanged): the summed squares fall from 40 to 30.4, counted
  // with the 520 independent values the refit leaves: 520 ln(30.4/40) + 2 ln 520 = -130.
  EffectiveSize two_before = size(10.0, 20.0), two_after = size(0.4, 20.0);
  for (EffectiveSize* z : {&two_before, &two_after}) {
    z->n[1] = 500;
    z->rss[1] = 30.0;
    z->n_eff[1] = 500.0;
  }
  const LadderDecision t = judge_rung(1, "rate_and_state", halved, two_after, before, two_before);
  EXPECT_NEAR(t.delta_ic, 520.0 * std::log(30.4 / 40.0) + 2.0 * std::log(520.0), 1e-9);
  EXPECT_TRUE(t.added) << t.reason;
}

// The effective number of independent residuals against its closed form: an AR(1) series with
// lag-1 correlation phi has n (1 - phi)/(1 + phi); white noise n; pairs across a stage boundary
// do not count; a residual that is one constant offset is worth the floor (10), not its rows.
TEST(Diagnosis, EffectiveSampleSizeMatchesTheAr1ClosedForm) {
  const std::size_t rows = 400000;  // the AR(1) estimate's scatter: n_eff within about 0.7 % (1 sigma)
  auto make = [&](const std::function<double(std::size_t)>& e0, const std::function<double(std::size_t)>& e1,
                  const std::function<int(std::size_t)>& stage) {
    MeasurementFile data;
    Segmentation seg;
    Comparison c;
    c.range = {2.0, 0.5};
    for (std::size_t i = 0; i < rows; ++i) {
      data.rows.push_back({static_cast<double>(i), stage(i), 1.0, 0.0, 0.0, 0.0});
      RowLabel l;
      l.stage = stage(i);
      seg.labels.push_back(l);
      c.alignment.model[0].push_back(2.0 * e0(i));  // residual e0 in units of the range
      c.alignment.model[1].push_back(0.5 * e1(i));
    }
    return effective_sample_size(data, seg, c);
  };
  std::mt19937 gen(7);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::vector<double> ar(rows), white(rows);
  const double phi = 0.9;
  ar[0] = normal(gen);
  for (std::size_t i = 1; i < rows; ++i) ar[i] = phi * ar[i - 1] + std::sqrt(1.0 - phi * phi) * normal(gen);
  for (auto& w : white) w = normal(gen);
  auto one = [](std::size_t) { return 1; };
  const EffectiveSize s = make([&](std::size_t i) { return ar[i]; }, [&](std::size_t i) { return white[i]; }, one);
  EXPECT_EQ(s.total_n(), 2 * rows);
  EXPECT_NEAR(s.r1[0], phi, 0.01);
  EXPECT_NEAR(s.r1[1], 0.0, 0.02);
  EXPECT_NEAR(s.n_eff[0] / (rows * (1.0 - phi) / (1.0 + phi)), 1.0, 0.05) << s.n_eff[0];
  EXPECT_NEAR(s.n_eff[1] / rows, 1.0, 0.05) << s.n_eff[1];
  EXPECT_NEAR(s.rss[1] / rows, 1.0, 0.03);
  // Alternating signs between stages of one row each: no pair is within a stage, so r1 = 0.
  const EffectiveSize alt = make([](std::size_t i) { return i % 2 ? 1.0 : -1.0; }, [](std::size_t) { return 0.0; },
                                 [](std::size_t i) { return static_cast<int>(i) + 1; });
  EXPECT_EQ(alt.r1[0], 0.0);
  EXPECT_NEAR(alt.total_n_eff(), 2.0 * rows, 1e-9);
  // One offset over every row: r1 -> 1, n_eff at the floor.
  const EffectiveSize offset = make([](std::size_t) { return 0.3; }, [](std::size_t) { return -0.2; }, one);
  EXPECT_GT(offset.r1[0], 0.999);
  EXPECT_DOUBLE_EQ(offset.n_eff[0], 5.0);
  EXPECT_DOUBLE_EQ(offset.total_n_eff(), 10.0);
}

// Blind: one hidden effect drawn from those a two-sided constant-rate record can reveal, with
// non-default parameters, and a noisy record, both from a seed. The seeds are 1 to 24 (both
// effects, twelve of each), not the clock: a clock seed made CI fail about one run in twelve,
// on the defect below (now fixed). ROCKDEM_BLIND_SEED runs one seed instead.
// Every rung must lower the reported error, and the first, the hidden effect, cut it by 30 % or
// more. Seeds 6 and 33975 (dilation_recovery hidden) used not to: its refit ended at 0.127 and
// 0.107 from 0.145, because at the fitting step the model joint lifted off for some of the
// parameter values the fit tried; with the element driver halving such increments both end at
// 0.0014, and since its normal solve follows a contracting joint's rising branch at 0.0009-0.0018
// (the record's noise; docs/validation.md section 1). 33975 is run as well as 1 to 24.
TEST(Diagnosis, BlindHiddenEffectIsRankedFirstAndCutsTheError) {
  struct Hidden {
    const char* effect;
    RawValues params;
  };
  const std::vector<Hidden> pool{
      {"reverse_shear_degradation", {{"weight", RawValue{2.5, "test"}}}},
      {"dilation_recovery", {{"residual_fraction", RawValue{0.4, "test"}}, {"hysteresis", RawValue{0.8, "test"}}}},
  };
  std::vector<unsigned> seeds;
  if (const char* env = std::getenv("ROCKDEM_BLIND_SEED")) {
    seeds.push_back(static_cast<unsigned>(std::stoul(env)));
  } else {
    for (unsigned k = 1; k <= 24; ++k) seeds.push_back(k);
    seeds.push_back(33975);
  }
  for (const unsigned seed : seeds) {
    std::mt19937 rng(seed);
    const Hidden& h = pool[std::uniform_int_distribution<std::size_t>(0, pool.size() - 1)(rng)];
    std::printf("blind diagnosis: seed %u (ROCKDEM_BLIND_SEED=%u repeats it), hidden effect %s\n", seed, seed, h.effect);
    RawValues law = kMc;
    law["dilation_angle"] = q("8 deg");
    law["dilation"] = q("monotonic");
    const MeasurementFile f = record(law, {EffectSpec{h.effect, h.params, "blind"}}, false, seed);
    const Segmentation seg = segment(f);
    DiagnosisOptions o = options({"reverse_shear_degradation", "dilation_recovery", "two_order_roughness"});
    o.base.law_values["dilation"] = q("monotonic");
    const Diagnosis d = diagnose(f, seg, o);
    ASSERT_FALSE(d.ranking.empty()) << "seed " << seed;
    EXPECT_EQ(d.ranking.front().effect, h.effect) << "seed " << seed << "\n" << format_report(d);
    // Every rung lowers the error the report shows, and its decision is recorded.
    for (std::size_t k = 1; k < d.ladder.size(); ++k) {
      EXPECT_LT(d.ladder[k].fit.nrmse[2], d.ladder[k - 1].fit.nrmse[2]) << "seed " << seed << ", rung " << k << "\n" << format_report(d);
      bool recorded = false;
      for (const auto& c : d.decisions) recorded = recorded || (c.step == k && c.added && c.effect == d.ladder[k].added);
      EXPECT_TRUE(recorded) << "seed " << seed << ", rung " << k;
    }
    const bool first = d.ladder.size() >= 2 && d.ladder[1].effects.front() == h.effect;
    const bool cut = first && d.ladder[1].fit.nrmse[2] < 0.7 * d.baseline.nrmse[2];  // a cut of 30 % or more
    std::printf("  first ranked %s; combined NRMSE %.4f, first rung %s %.4f\n", d.ranking.front().effect.c_str(), d.baseline.nrmse[2],
                d.ladder.size() >= 2 ? d.ladder[1].effects.front().c_str() : "(none)", d.ladder.size() >= 2 ? d.ladder[1].fit.nrmse[2] : NAN);
    EXPECT_TRUE(first) << "seed " << seed << "\n" << format_report(d);
    EXPECT_TRUE(cut) << "seed " << seed << ": " << (d.ladder.size() >= 2 ? d.ladder[1].fit.nrmse[2] : NAN) << " against "
                     << d.baseline.nrmse[2] << "\n" << format_report(d);
  }
}

namespace {

// A slide-hold-slide record in one direction at 0.042 mm/s: slides of 2 mm separated by holds of
// `holds_s` (in that order), Mohr-Coulomb with rate-and-state friction, one stage at 2 MPa, every
// increment kept, seeded noise as noisy_record.hpp's.
MeasurementFile slide_hold_slide(const std::vector<EffectSpec>& effects, const std::vector<double>& holds_s, unsigned seed) {
  RawValues law = kMc;
  law["dilation_angle"] = q("0 deg");
  auto model = make_joint_model("mohr_coulomb", law, effects, "test");
  ElementOptions eo;
  eo.max_step = 2.5e-5;
  eo.length = 0.2;
  ElementDriver d(*model, eo);
  std::vector<ElementStage> stages(1);
  stages[0].normal_stress = 2e6;
  stages[0].path = testutil::slide_hold_slide_path(4.2e-5, 2e-3, holds_s);
  MeasurementFile f = d.run(stages);
  testutil::add_noise(f, seed);
  f.metadata.push_back({"joint_length_m", "0.2"});
  return f;
}

const EffectSpec kHealing{"rate_and_state",
                          {{"a", RawValue{0.01, "test"}}, {"b", RawValue{0.03, "test"}}, {"critical_slip", q("100 um")}},
                          "test"};

}  // namespace

// Holds are found (the element driver writes a pause as one long increment), a slide-hold-slide
// record at one rate can reveal rate-and-state healing (the constant-rate record without holds
// cannot), and time_since_motion carries each hold's length onto the slide after it.
TEST(Diagnosis, HoldsAreFoundAndMakeHealingJudgeable) {
  const std::vector<double> holds{100.0, 10.0, 1000.0};
  const MeasurementFile f = slide_hold_slide({kHealing}, holds, 7);
  const Segmentation seg = segment(f);
  const std::vector<Hold> found = find_holds(f, seg);
  ASSERT_EQ(found.size(), holds.size());
  for (std::size_t k = 0; k < holds.size(); ++k) {
    EXPECT_NEAR(found[k].duration_s, holds[k], 1e-9 * holds[k]) << k;
    EXPECT_TRUE(found[k].followed_by_motion) << k;
  }
  const RecordFeatures rf = record_features(f, seg);
  EXPECT_EQ(rf.holds, 3);
  EXPECT_NEAR(rf.longest_hold_s, 1000.0, 1e-6);
  EXPECT_EQ(unjudgeable_reason("rate_and_state", rf), "");
  // The same slides without holds: one rate, nothing held.
  const MeasurementFile plain = slide_hold_slide({kHealing}, {}, 7);
  EXPECT_NE(unjudgeable_reason("rate_and_state", plain, segment(plain)).find("never held still"), std::string::npos);
  const Covariates c = row_covariates(f, seg);
  ASSERT_EQ(c.names.back(), "time_since_motion");
  const auto& tsm = c.values.back();
  // The slide after each hold carries that hold's length; the first slide none.
  EXPECT_EQ(tsm[found[0].begin], 0.0);
  EXPECT_NEAR(tsm[found[0].end + 1], 100.0, 1e-9);
  EXPECT_NEAR(tsm[found[1].begin], 100.0, 1e-9);
  EXPECT_NEAR(tsm[found[1].end + 1], 10.0, 1e-9);
  EXPECT_NEAR(tsm[found[2].end + 1], 1000.0, 1e-9);
  EXPECT_NEAR(tsm.back(), 1000.0, 1e-9);
}

// Holds logged at a fixed rate (1 Hz), as a laboratory records them, are most of the stage's
// intervals (4,000 s at rest against 190 s of sliding): they are still found.
TEST(Diagnosis, LongHoldsLoggedAtAFixedRateAreFound) {
  MeasurementFile f;
  double t = 0.0, u = 0.0;
  const auto add = [&](double du) {
    f.rows.push_back({t, 1, 2.0, u, 1.2, 0.0});
    t += 1.0;
    u += du;
  };
  for (const double hold : {1000.0, 3000.0, 0.0}) {
    for (int i = 0; i < 48; ++i) add(0.042);  // 2 mm at 0.042 mm/s
    for (int i = 0; i < static_cast<int>(hold); ++i) add(0.0);
  }
  add(0.0);
  const Segmentation seg = segment(f);
  const std::vector<Hold> holds = find_holds(f, seg);
  ASSERT_EQ(holds.size(), 2u);
  EXPECT_NEAR(holds[0].duration_s, 1000.0, 1.0);
  EXPECT_NEAR(holds[1].duration_s, 3000.0, 1.0);
  EXPECT_TRUE(holds[0].followed_by_motion && holds[1].followed_by_motion);
  EXPECT_EQ(record_features(f, seg).holds, 2);
}

// Diagnose on that record, not told: rate_and_state is judged, ranked first and cuts the error;
// the effects a one-sided record cannot reveal are listed as not judged and do not make the
// answer "not confident".
TEST(Diagnosis, SlideHoldSlideHealingIsFoundWithAConfidentAnswer) {
  const MeasurementFile f = slide_hold_slide({kHealing}, {100.0, 10.0, 1000.0}, 11);
  const Segmentation seg = segment(f);
  DiagnosisOptions o = options({"rate_and_state", "reverse_shear_degradation", "directional_wear", "two_order_roughness"});
  o.base.law_values["dilation_angle"] = q("0 deg");
  o.base.fix["dilation_angle"] = 0.0;
  o.base.element.max_step = 2.5e-5;
  o.base.fit_step = 2.5e-5;
  const Diagnosis d = diagnose(f, seg, o);
  std::printf("%s", format_report(d).c_str());
  ASSERT_FALSE(d.ranking.empty());
  EXPECT_EQ(d.ranking.front().effect, "rate_and_state") << format_report(d);
  ASSERT_GE(d.ladder.size(), 2u) << format_report(d);
  EXPECT_EQ(d.ladder[1].effects.front(), "rate_and_state");
  // The shear stress carries the healing; the normal displacement is noise here (no dilation),
  // which holds the combined NRMSE near 0.1 whatever the model.
  EXPECT_LT(d.ladder[1].fit.nrmse[0], d.baseline.nrmse[0] / 3.0) << format_report(d);
  const auto value = [&](const std::string& name) {
    for (const auto& p : d.ladder[1].fit.params)
      if (p.name == name) return p.value;
    return std::nan("");
  };
  EXPECT_NEAR(value("rate_and_state.a"), 0.01, 0.001);
  EXPECT_NEAR(value("rate_and_state.b"), 0.03, 0.003);
  EXPECT_NEAR(value("rate_and_state.critical_slip"), 100e-6, 10e-6);
  EXPECT_TRUE(d.confident) << format_report(d);
  const nlohmann::json j = to_json(d, "shs.csv");
  bool listed = false;
  for (const auto& e : j["not_judged"]) listed = listed || e["effect"] == "reverse_shear_degradation";
  EXPECT_TRUE(listed) << j["not_judged"].dump();
  EXPECT_TRUE(j["doubts"].empty());
}

// One badly fitted stage: a stage-level offset (0.1 of the range on stage 2) would put
// normal_stress first and hide the dependence inside the stages (0.03 when shearing back). With
// each stage's mean removed, toward_origin comes first and the offset is reported on its own.
TEST(Diagnosis, StageOffsetsAreReportedApartFromCovariatesWithinStages) {
  const MeasurementFile f = record(kMc, {}, false, 5);
  const Segmentation seg = segment(f);
  ASSERT_EQ(seg.stages.size(), 2u);
  std::mt19937 rng(9);
  std::normal_distribution<double> g(0.0, 0.005);
  std::array<std::vector<double>, 2> r;
  for (std::size_t i = 0; i < f.rows.size(); ++i) {
    r[0].push_back((seg.labels[i].stage == 2 ? 0.1 : 0.0) + (seg.labels[i].direction < 0 ? 0.03 : 0.0) + g(rng));
    r[1].push_back(g(rng));
  }
  const Covariates c = row_covariates(f, seg);
  const auto top_tau = [](const std::vector<CovariateScore>& s) {
    for (const auto& x : s)
      if (x.variable == "shear_stress") return x.name;
    return std::string();
  };
  EXPECT_EQ(top_tau(score_covariates(c, r)), "normal_stress");  // what the stage offset did before
  EXPECT_EQ(top_tau(score_covariates(c, within_stages(seg, r))), "toward_origin");
  const StageOffsets so = stage_offsets(f, seg, r);
  ASSERT_EQ(so.stages.size(), 2u);
  EXPECT_NEAR(so.stages[1].mean[0] - so.stages[0].mean[0], 0.1, 0.005);
  EXPECT_NEAR(so.stages[0].normal_stress_MPa, 2.0, 0.01);
  EXPECT_NEAR(so.stages[1].normal_stress_MPa, 4.0, 0.01);
  EXPECT_NEAR(so.stages[0].rate_mm_s, 0.042, 0.001);
  EXPECT_GT(so.share[0], 0.7);
  EXPECT_LT(so.share[1], 0.01);
  // Within stages, every stage's mean is zero.
  const auto w = within_stages(seg, r);
  for (const auto& st : seg.stages) {
    double sum = 0.0;
    for (std::size_t i = st.begin; i < st.end; ++i) sum += w[0][i];
    EXPECT_NEAR(sum / static_cast<double>(st.end - st.begin), 0.0, 1e-12);
  }
}

// The base law's shape first: a Continuously-Yielding record (dilation decaying with wear, none
// given back on reverse shearing) diagnosed with Mohr-Coulomb (constant dilation) is a warning and
// a doubt naming the better law; with --law best the effects are judged on Continuously-Yielding,
// and dilation_recovery, which the record does not have, is not credited with the shape.
TEST(Diagnosis, BaseLawCheckNamesABetterShapeAndBestUsesIt) {
  const RawValues cy{{"kn", q("40 GPa/m")},     {"ks", q("15 GPa/m")},    {"initial_friction", q("50 deg")},
                     {"friction", q("32 deg")}, {"roughness", q("3 mm")}, {"dilation", q("monotonic")}};
  auto model = make_joint_model("continuously_yielding", cy, {}, "test");
  const MeasurementFile f = testutil::noisy_two_stage_record(*model, 2.5e-5, 4, false, 21);
  const Segmentation seg = segment(f);
  DiagnosisOptions o = options({"dilation_recovery", "reverse_shear_degradation"});
  o.base.element.max_step = 2.5e-5;
  o.base.fit_step = 5e-5;
  o.base.law_values["dilation"] = q("monotonic");
  o.check_base_laws = true;
  const Diagnosis named = diagnose(f, seg, o);
  std::printf("%s", format_report(named).c_str());
  ASSERT_FALSE(named.base_laws.empty());
  EXPECT_EQ(named.base_laws.front().law, "continuously_yielding") << format_report(named);
  EXPECT_EQ(named.base_laws.size(), 9u);  // three laws, three dilation modes each
  for (std::size_t i = 1; i < named.base_laws.size(); ++i)
    if (!named.base_laws[i].failed) {
      EXPECT_LE(named.base_laws[i - 1].fit.bic, named.base_laws[i].fit.bic);
    }
  // No critical shear displacement given: udec_legacy is reversible's model, fitted once.
  for (const auto& l : named.base_laws) {
    if (l.dilation != "udec_legacy") continue;
    EXPECT_EQ(l.same_as, "reversible") << l.law;
    for (const auto& r : named.base_laws) {
      if (r.law == l.law && r.dilation == "reversible") {
        EXPECT_EQ(r.fit.bic, l.fit.bic) << l.law;
      }
    }
    EXPECT_EQ(l.fit.settings.at("dilation"), "udec_legacy");
  }
  bool warned = false;
  for (const auto& w : named.warnings)
    warned = warned || (w.find("continuously_yielding with dilation") != std::string::npos &&
                        w.find("fits this record much better than mohr_coulomb with dilation = monotonic") != std::string::npos);
  EXPECT_TRUE(warned) << format_report(named);
  EXPECT_FALSE(named.confident);
  ASSERT_FALSE(named.doubts.empty());
  EXPECT_NE(named.doubts.front().find("another base law fits much better"), std::string::npos) << named.doubts.front();

  o.use_best_base_law = true;
  const Diagnosis best = diagnose(f, seg, o);
  std::printf("%s", format_report(best).c_str());
  EXPECT_EQ(best.law, "continuously_yielding");
  EXPECT_TRUE(best.law_chosen);
  EXPECT_EQ(to_json(best, "cy.csv")["base_law"], "continuously_yielding");
  EXPECT_LT(best.baseline.nrmse[2], 0.5 * named.baseline.nrmse[2]) << format_report(best);
  for (const auto& rung : best.ladder)
    for (const auto& e : rung.effects) EXPECT_NE(e, "dilation_recovery") << format_report(best);
}

// Clean controls, one per base law: a two-sided cyclic record made by the law alone (its own
// dilation mode) with white noise, diagnosed with that law and the whole catalogue. Nothing may be
// added: white residuals are worth n_eff close to n, and no effect's few parameters pay for
// fitting noise. (The clean-control test; the blind test draws only hidden effects.)
TEST(Diagnosis, CleanRecordsOfEachBaseLawGetNoEffect) {
  struct Law {
    const char* name;
    RawValues values;
  };
  const std::vector<Law> laws{
      {"mohr_coulomb", kMc},
      {"barton_bandis", testutil::barton_bandis_joint()},
      {"continuously_yielding", testutil::continuously_yielding_joint()},
  };
  for (const Law& law : laws) {
    auto model = make_joint_model(law.name, law.values, {}, "test");
    const MeasurementFile f = testutil::noisy_two_stage_record(*model, 2.5e-5, 4, false, 11);
    const Segmentation seg = segment(f);
    DiagnosisOptions o = options({});  // every physical effect registered
    o.base.law = law.name;
    o.base.law_values.clear();
    o.base.law_values["dilation"] = law.values.at("dilation");
    o.base.law_values["kn"] = law.values.at("kn");
    o.base.element.max_step = 2.5e-5;
    o.base.fit_step = 5e-5;
    const Diagnosis d = diagnose(f, seg, o);
    std::printf("clean %s: baseline combined NRMSE %.4f, n_eff %.0f of %zu\n", law.name, d.baseline.nrmse[2],
                d.baseline_size.total_n_eff(), d.baseline_size.total_n());
    EXPECT_EQ(d.ladder.size(), 1u) << law.name << "\n" << format_report(d);
    EXPECT_GT(d.baseline_size.total_n_eff(), 0.5 * static_cast<double>(d.baseline_size.total_n()))
        << law.name << "\n" << format_report(d);
    EXPECT_LT(d.baseline.nrmse[2], 0.05) << law.name << "\n" << format_report(d);
  }
}

// A two-sided noisy record of Mohr-Coulomb with reversible dilation (the base-law check's tests).
MeasurementFile reversible_mohr_coulomb_record() {
  auto model = make_joint_model("mohr_coulomb",
                                RawValues{{"kn", q("40 GPa/m")}, {"ks", q("12 GPa/m")}, {"friction", q("36 deg")},
                                          {"dilation_angle", q("5 deg")}, {"dilation", q("reversible")}},
                                {}, "test");
  return testutil::noisy_two_stage_record(*model, 2.5e-5, 4, false, 5);
}

// udec_legacy stops giving dilation back once the critical shear displacement has been reached:
// with one given to the named law, its udec_legacy is another model and is fitted (its value
// is not carried to the other laws, whose udec_legacy stays reversible's model).
TEST(Diagnosis, BaseLawCheckFitsUdecLegacyWhereTheCriticalShearDisplacementIsGiven) {
  const MeasurementFile f = reversible_mohr_coulomb_record();
  const Segmentation seg = segment(f);
  CalibrationOptions base;
  base.law = "mohr_coulomb";
  base.element.max_step = 2.5e-5;
  base.fit_step = 5e-5;
  base.law_values["critical_shear_disp"] = q("2 mm");
  const std::vector<BaseLawFit> fits = fit_base_laws(f, seg, base, 2);
  int legacy = 0;
  for (const auto& l : fits) {
    if (l.dilation != "udec_legacy") continue;
    ++legacy;
    EXPECT_EQ(l.same_as, l.law == "mohr_coulomb" ? "" : "reversible") << l.law;
    EXPECT_FALSE(l.failed) << l.law << ": " << l.reason;
  }
  EXPECT_EQ(legacy, 3);
  const auto mc = [&](const std::string& mode) {
    return std::find_if(fits.begin(), fits.end(), [&](const BaseLawFit& l) { return l.law == "mohr_coulomb" && l.dilation == mode; });
  };
  ASSERT_NE(mc("udec_legacy"), fits.end());
  ASSERT_NE(mc("reversible"), fits.end());
  EXPECT_NE(mc("udec_legacy")->fit.rss, mc("reversible")->fit.rss);
  EXPECT_GT(mc("udec_legacy")->fit.evaluations, 0);
}

// The ladder's order: of the candidates that pay, the lowest combined NRMSE first, whatever their
// delta IC (each is weighted by the n_eff it leaves); then the others by delta IC; NaN never pays.
TEST(Diagnosis, CandidatesThatPayAreTriedLowestErrorFirst) {
  const double now = 0.249;
  // Test 9's twin with Continuously-Yielding: reverse_shear_degradation (-715, 0.146) and
  // dilation_recovery (-523, 0.065): dilation_recovery first.
  EXPECT_TRUE(effect_tried_before(-523.0, 0.065, -715.0, 0.146, now));
  EXPECT_FALSE(effect_tried_before(-715.0, 0.146, -523.0, 0.065, now));
  // One that pays before one that does not (a higher IC, or an error cut by less than 0.1 %).
  EXPECT_TRUE(effect_tried_before(-1.0, 0.24, -900.0, 0.2489, now));
  EXPECT_TRUE(effect_tried_before(-1.0, 0.24, +5.0, 0.01, now));
  // Neither pays: by delta IC.
  EXPECT_TRUE(effect_tried_before(+3.0, 0.30, +9.0, 0.20, now));
  EXPECT_FALSE(effect_tried_before(+9.0, 0.20, +3.0, 0.30, now));
  // NaN error: never pays; irreflexive.
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(effect_tried_before(-1.0, 0.2, -50.0, nan, now));
  EXPECT_FALSE(effect_tried_before(-1.0, 0.2, -1.0, 0.2, now));
}

// With reversible named and no critical shear displacement, the udec_legacy row is the named
// mode's own model: it is neither "another dilation mode that fits better" nor the named law's best
// mode that another law is measured against. On a Mohr-Coulomb record nothing fits much better;
// on a Continuously-Yielding record CY does, and the warning compares it with Mohr-Coulomb as named
// or in a mode that is another model.
TEST(Diagnosis, TheNamedModesSharedRowIsNotAnotherMode) {
  auto cy = make_joint_model("continuously_yielding",
                             RawValues{{"kn", q("40 GPa/m")}, {"ks", q("15 GPa/m")}, {"initial_friction", q("50 deg")},
                                       {"friction", q("32 deg")}, {"roughness", q("3 mm")}, {"dilation", q("monotonic")}},
                             {}, "test");
  for (const MeasurementFile& f : {reversible_mohr_coulomb_record(), testutil::noisy_two_stage_record(*cy, 2.5e-5, 4, false, 21)}) {
    const Segmentation seg = segment(f);
    DiagnosisOptions o = options({"dilation_recovery"});
    o.base.element.max_step = 2.5e-5;
    o.base.fit_step = 5e-5;
    o.base.law_values["dilation"] = q("reversible");
    o.check_base_laws = true;
    const Diagnosis d = diagnose(f, seg, o);
    for (const auto& w : d.warnings) {
      EXPECT_EQ(w.find("udec_legacy fits this record"), std::string::npos) << w;
      EXPECT_EQ(w.find("(udec_legacy)"), std::string::npos) << w;
    }
  }
}
