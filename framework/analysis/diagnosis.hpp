#pragma once
// Diagnosis of a joint law against a record: which physical effect is missing?
//   1. calibrate the base law (calibration.hpp);
//   2. localise the misfit by variable, stage, cycle and quadrant (compare's segments, worst lines);
//   3. explain the residual by physical covariates per row (offset, toward_origin, cumulative_slip,
//      cycle, velocity, normal_stress, fresh_surface, time_since_motion) within stages: each
//      stage's mean residual is removed first and reported on its own (stage_offsets), so that one
//      badly fitted stage does not put a stage-level covariate (normal stress, rate) first and
//      hide a dependence inside the stages. The score is the adjusted correlation ratio eta^2 of
//      the residual binned on the covariate (Fisher's eta^2, corrected for the number of bins like
//      an adjusted R^2), i.e. the share of the residual's variance its bin means explain;
//   4. for every effect of the EffectRegistry (but those that declare themselves not physical,
//      see non_physical_effects()), add it, recalibrate it with the base law (warm start), and rank by
//      an information criterion on the range-normalised residuals the fit minimises, whose
//      sample size is the effective number of independent residuals, not the number of rows:
//        IC = n_eff ln(RSS/n) + k ln(n_eff),  n_eff = sum_v n_v (1 - r1_v)/(1 + r1_v)
//      i.e. the BIC (Schwarz 1978) with its log-likelihood divided by the variance inflation
//      n/n_eff of correlated residuals, as QAIC divides it by an overdispersion factor (Burnham &
//      Anderson 2002, sec. 2.5), n_eff from the AR(1) approximation of the effective sample size
//      of an autocorrelated series (reviewed by Bretherton et al. 1999), r1_v the lag-1
//      autocorrelation of variable v's residual within stages left by the chain with the effect
//      (the larger of two nested models estimates the noise); then climb a ladder: add the best
//      effect while the IC and the combined NRMSE the report shows both fall (the NRMSE by 0.1 % or
//      more), each new effect fitted from two starts (its lone fit's values and its defaults);
//   5. JSON (to_json) and, with a report folder, the files plotted by scripts/plot_diagnosis.py.
// Effects that the record cannot reveal (no reverse shearing, one side only, one rate, ...; each
// effect says so itself from the record's features) are named with the reason and kept out of
// the ladder. docs/user-guide-calibrate-diagnose.md.
#include <array>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "framework/analysis/calibration.hpp"
#include "framework/analysis/effective_size.hpp"
#include "framework/plugin_api/record_features.hpp"

namespace rockdem {

struct DiagnosisOptions {
  CalibrationOptions base;           // the base law, element settings, stages, fixes
  std::vector<std::string> effects;  // effects to try; empty: every physical effect registered
  int threads = 2;                   // effect fits in parallel
  int bins = 10;                     // covariate bins (quantiles; fewer for discrete covariates)
  // Fit also the effects the record cannot reveal (their numbers then only say how the effect's
  // side effects bend the law; they stay out of the ladder). Off: they are named, not fitted.
  bool fit_unjudged = false;
  // Before any effect, fit the standard base laws with each dilation mode (fit_base_laws) and say
  // which shape fits: an effect must not be credited with what another base law does anyway.
  bool check_base_laws = true;
  // Run the effects on the base law and dilation mode that fit best (lowest BIC) instead of
  // base.law (`rockdem diagnose --law best`); implies check_base_laws.
  bool use_best_base_law = false;
  // Told one line for each fit as it finishes (base laws, the baseline, each effect alone, each
  // rung's candidates), with the time since the diagnosis began; a 40-cycle record takes minutes
  // and the user must see that it moves, and where. Calls are serialised (fits run on threads).
  std::function<void(const std::string&)> progress;
};

// One base law with one dilation mode fitted to the record without effects.
struct BaseLawFit {
  std::string law, dilation;
  bool failed = false;
  std::string reason;     // why the fit failed
  CalibrationResult fit;  // when not failed
  // Another mode of the same law that is the same model here, whose fit this one is (not fitted
  // again): udec_legacy is reversible where the critical shear displacement is infinite.
  std::string same_as;
};
// The standard laws (mohr_coulomb, barton_bandis, continuously_yielding; and base.law if it is
// another) with each of their `dilation` modes, fitted to the record with base's stages and
// element settings, and with those of base's starting values and fixes whose names the law
// shares (kn, ks: measured on the specimen whatever the law); best (lowest BIC) first, failed
// fits last. `threads` fits run at a time. Each is one start without the fine-step polish or
// profiles; diagnose() then shows its baseline's fit (profiled, polished) in the row of the named
// law and mode.
// `done`, if given, is called after each fit (from the thread that ran it).
std::vector<BaseLawFit> fit_base_laws(const MeasurementFile& data, const Segmentation& seg, const CalibrationOptions& base,
                                      int threads, const std::function<void(const BaseLawFit&)>& done = {});

// Per-row covariates of a record (one vector per covariate, one value per row).
struct Covariates {
  std::vector<std::string> names;
  std::vector<std::vector<double>> values;
};
Covariates row_covariates(const MeasurementFile& data, const Segmentation& seg);

// A stretch of a stage in which the joint is held still (slide-hold-slide tests, pauses between
// shearing episodes). Rows [begin, end] span it: `begin` is the last row before it stops, `end`
// the last row still at rest; an interval counts as at rest when its shear rate is below 1 % of
// the slide rate (the 90th percentile of the intervals that move). Displacement noise larger than
// that on a held joint splits a hold (not yet handled: records with a noisy displacement channel
// during holds need a windowed test).
struct Hold {
  int stage = 0;
  std::size_t begin = 0, end = 0;
  double duration_s = 0.0;
  bool followed_by_motion = false;  // the joint shears again later in the stage
};
std::vector<Hold> find_holds(const MeasurementFile& data, const Segmentation& seg);

// A stage's mean residual (signed as the covariates' residual: positive = model too strong in
// shear, too much dilation), with what the stage was run at.
struct StageOffset {
  int stage = 0;
  std::size_t rows = 0;
  double normal_stress_MPa = 0.0;  // the stage's median
  double rate_mm_s = 0.0;          // median shear rate over its moving rows
  std::array<double, 2> mean{};    // per variable, in units of the variable's range
};
struct StageOffsets {
  std::vector<StageOffset> stages;
  // Share of each variable's residual sum of squares (about its mean) that the stage means
  // explain (eta^2 on the stage, not adjusted: a handful of stages).
  std::array<double, 2> share{};
};
StageOffsets stage_offsets(const MeasurementFile& data, const Segmentation& seg,
                           const std::array<std::vector<double>, 2>& residual);
// `residual` with each stage's mean removed (per variable).
std::array<std::vector<double>, 2> within_stages(const Segmentation& seg, std::array<std::vector<double>, 2> residual);

struct CovariateScore {
  std::string variable;  // "shear_stress", "normal_disp"
  std::string name;
  double score = 0.0;    // adjusted eta^2 in [0, 1]
};
// Scores of every covariate for each residual vector (residual[v][row]), best first.
std::vector<CovariateScore> score_covariates(const Covariates& cov, const std::array<std::vector<double>, 2>& residual,
                                             int bins = 10);

// Effects of the registry that declare themselves not physical (`physical = false`, e.g.
// strength_reduction: a factor of safety device that scales the strength): never tried.
std::vector<std::string> non_physical_effects();
// The others, in registry order: the effects diagnose tries when none are named.
std::vector<std::string> physical_effects();

// What the record shows that decides whether an effect can be revealed by it (plugin_api's
// neutral description, so that effects can judge it without seeing records).
RecordFeatures record_features(const MeasurementFile& data, const Segmentation& seg);

// Why a record cannot reveal an effect ("" if it can, or if the effect declares no rule or is
// unknown): the effect's own `unjudgeable` declaration (framework/plugin_api/effect.hpp).
std::string unjudgeable_reason(const std::string& effect, const RecordFeatures& features);
std::string unjudgeable_reason(const std::string& effect, const MeasurementFile& data, const Segmentation& seg);

// EffectiveSize, effective_sample_size: framework/analysis/effective_size.hpp.

// IC = n_eff ln(RSS/n) + k ln(n_eff), RSS = fit.rss summed over both variables (the sum the fit
// minimises), n = fit's residuals, n_eff = weights.total_n_eff(): the fit's residuals counted as
// n_eff independent values. With white weights (n_eff = n) it is the BIC the calibration reports.
// (Per-variable log-likelihoods, each variable with its own variance, were tried: a refit that
// trades a little of a variable fitted to its noise level for a large cut in the other then
// scores worse, against the combined NRMSE the report shows; seeds 15 and 23 of the blind test.)
double information_criterion(const EffectiveSize& fit, int k, const EffectiveSize& weights);

// What adding an effect buys: IC(with) - IC(without), both counted with the effective sizes of
// the residuals `with` leaves (the larger model's residuals estimate the noise, as in a nested
// test: what the effect could not explain is what its gain is weighed against). Negative: the
// effect pays for its parameters.
double delta_ic(const EffectiveSize& with, int k_with, const EffectiveSize& without, int k_without);

struct EffectTrial {
  std::string effect;
  bool revealable = true;   // the record can reveal it (its unjudgeable rule says nothing)
  bool judged = true;
  std::string reason;       // why not judged, or why the fit failed
  bool failed = false;
  bool fitted = false;      // false: failed, or not judged and not fitted (DiagnosisOptions::fit_unjudged)
  CalibrationResult fit;
  double delta_bic = 0.0;   // fit.bic - baseline BIC (for reference: counts every row as independent)
  double delta_ic = 0.0;    // delta_ic against the baseline (negative: pays for its parameters)
  EffectiveSize size;       // of its residuals
};

struct LadderStep {
  std::vector<std::string> effects;  // in composition order (the order the joint applies them)
  CalibrationResult fit;
  EffectiveSize size;  // of this step's residuals (reported; a rung is judged with the n_eff it leaves)
  std::string added;   // the effect this rung added (empty on the baseline); first or last in `effects`
};

// Why the ladder took, or did not take, an effect at one step: a rung must lower the IC
// (delta_ic) and the combined NRMSE the report shows (by kLadderMinCut of it or more); of those
// that do, the one with the lowest combined NRMSE is taken.
struct LadderDecision {
  std::size_t step = 0;        // the rung it was tried for (1: the first effect)
  std::string effect;
  bool added = false;
  double n_eff = 0.0;          // of the chain with the effect (both variables): delta_ic's weights
  double delta_ic = 0.0;       // against the step before
  double delta_bic = 0.0;      // the same with n_eff = n (for reference)
  double nrmse_before = 0.0, nrmse_after = 0.0;  // combined
  // Where in the chain it was fitted: first (before the effects already there) or last; the
  // other order's combined NRMSE where it was fitted too (NaN: the order does not change the
  // model at the fitted values, or this is the first rung).
  bool composed_first = false;
  double nrmse_other_order = std::numeric_limits<double>::quiet_NaN();
  std::string reason;
};

struct Diagnosis {
  std::string law;
  CalibrationResult baseline;
  std::vector<BaseLawFit> base_laws;       // the base-law check, best first (empty: not run)
  bool law_chosen = false;                 // `law` is the check's best, not the user's
  std::vector<CovariateScore> covariates;  // within stages, best first
  StageOffsets stage_offsets;              // the baseline residual's stage means
  EffectiveSize baseline_size;             // the baseline's residuals
  std::vector<EffectTrial> ranking;        // judged: those that pay first (effect_tried_before); then the ones not judged
  std::vector<LadderStep> ladder;          // first: the baseline
  std::vector<LadderDecision> decisions;   // every effect tried for a rung, in order
  std::vector<std::string> warnings;
  // Whether the answer can be acted on: false when the record is short, when an effect that the
  // record could reveal could not be fitted (it may be the missing one), or when two effects
  // explain the misfit about equally (the first rung is a toss-up). Effects the record cannot
  // reveal do not count: they cannot change this record's model, so the verdict on it stands;
  // they are listed in `not_judged` (and the warnings) instead.
  bool confident = true;
  std::vector<std::string> doubts;         // why not confident (empty when confident)
  double wall_ms = 0.0;
};

Diagnosis diagnose(const MeasurementFile& data, const Segmentation& seg, const DiagnosisOptions& options);

// The smallest relative cut of the combined NRMSE that counts as lowering it (0.1 %): below it a
// refit has only moved the error by rounding (an effect that changes nothing still "lowers" the
// IC by -0.0 and the error in its last digits; the broad blind test caught such a rung).
inline constexpr double kLadderMinCut = 1e-3;

// The order the ladder tries candidates in (and the ranking lists them): a is before b. Those that
// pay (delta IC < 0, and the combined NRMSE below (1 - kLadderMinCut) of nrmse_now, the error
// without them) first, the lowest combined NRMSE first, since that is the error the report shows;
// then the others by delta IC. By delta IC alone, an effect that whitens the residual came before
// one that cuts it far more, since each is weighted by the n_eff it leaves (test 9's twin with
// Continuously-Yielding: reverse_shear_degradation, 0.249 -> 0.146 with n_eff 640, delta IC -715,
// before dilation_recovery, 0.249 -> 0.065 with n_eff 172, -523). A NaN error never pays.
bool effect_tried_before(double delta_ic_a, double nrmse_a, double delta_ic_b, double nrmse_b, double nrmse_now);

// The ladder's rule for one candidate rung: `fit` (the chain with `effect` added, residuals
// `fit_size`) against `before` (the chain without it, `before_size`) is added when it lowers both
// the IC (delta_ic) and the combined NRMSE, the latter by at least kLadderMinCut of it.
LadderDecision judge_rung(std::size_t step, const std::string& effect, const CalibrationResult& fit,
                          const EffectiveSize& fit_size, const CalibrationResult& before, const EffectiveSize& before_size);

// The JSON of the issue: data, base_law, baseline, segments, covariates, stage_offsets, ranking,
// ladder, ladder_decisions, final, plus warnings, confident, doubts, not_judged, worst.
nlohmann::json to_json(const Diagnosis& d, const std::string& data_file);
std::string format_report(const Diagnosis& d);

// Report files for scripts/plot_diagnosis.py: <dir>/aligned.csv (per measured row: stage, cycle,
// quadrant, shear displacement, the measurement and each ladder step's aligned model).
void write_report_data(const Diagnosis& d, const MeasurementFile& data, const std::string& dir);

}  // namespace rockdem
