#pragma once
// Calibration of a joint law (+ ordered effects) to a single-joint shear record: bounded nonlinear
// least squares (Ceres, Levenberg-Marquardt) on the residuals `rockdem compare` computes, each
// divided by the measured variable's range over the whole file, so the objective is
//   sum_i rho((model_i - measured_i)^2 / range_v^2) = n_tau NRMSE_tau^2 + n_n NRMSE_n^2 (rho = id),
// with rho the soft-L1 loss 2c^2(sqrt(1 + s/c^2) - 1) (Triggs et al. 2000 correction in Ceres) so
// that chatter spikes and outliers larger than c (default 10 % of the range) pull linearly, not
// quadratically. Free parameters are mapped to [0, 1] (log scale for stiffnesses, lengths,
// stresses, energies, velocities), their bounds being the registry's ranges tightened to
// physical ones; starting values come from the record itself (initial slope, peak and
// end-of-stroke strength, dilation slope). The model runs on the element driver with the
// record's own shear path (or a laboratory case's stages); the fit uses a coarser step than the
// final evaluation (both NRMSEs are reported). Standard errors from the Jacobian at the optimum:
// Cov = (J^T J)^-1 s^2, s^2 = RSS/(n - k) (residuals treated as independent: a lower bound when
// the misfit is systematic). docs/user-guide-calibrate-diagnose.md describes all of it.
#include <array>
#include <limits>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "framework/analysis/compare.hpp"
#include "framework/core/params.hpp"
#include "framework/io/measurement_csv.hpp"
#include "framework/lab/element_driver.hpp"

namespace rockdem {

struct CalibrationOptions {
  std::string law;
  std::vector<std::string> effects;  // in chain order
  // Starting (and fixed) values as written (a laboratory case's [joint.params], effect tables);
  // parameters not given start from the data estimates or the registry default.
  RawValues law_values;
  std::map<std::string, RawValues> effect_values;
  // Fixed at these values [SI]; names: a law parameter ("friction") or "effect.param"
  // ("rate_and_state.a"); an effect parameter may be named alone when that is unambiguous.
  std::map<std::string, double> fix;
  // The same as written on the command line ("30 deg", "0.5"), parsed with the parameter's unit
  // and range (InputError naming the parameter otherwise).
  std::map<std::string, std::string> fix_text;
  // Parameters fixed by default (each law's and effect's `fixed_by_default` declaration) to fit
  // nevertheless.
  std::vector<std::string> free;
  // If not empty, only these parameters are free (the others keep their starting values):
  // diagnose refits an effect's parameters plus the base law's.
  std::vector<std::string> only_free;
  // Starting values [SI] overriding the estimates (warm starts).
  std::map<std::string, double> start;
  // The starting values are an optimum already (a refit of a fitted chain with more parameters
  // free): taken as they are, a value on its bound kept there. Otherwise every start is moved a
  // little inside its bounds (a default on a bound, an effect's "off" value, is a poor start).
  bool start_is_optimum = false;
  // Other starting values for some of the free parameters (each map a point: its parameters
  // replace the start's, the rest kept). Each is run once at the fitting step and the fit starts
  // from the point of the lowest objective, the start above included (diagnose: a rung
  // candidate's values at the rung below, against its registry defaults).
  std::vector<std::map<std::string, double>> other_starts;
  // Stages to run; empty: from the data (its normal stress per stage, its shear path as a table).
  std::vector<ElementStage> stages;
  ElementOptions element;           // the final evaluation (max_step: the fine step)
  double fit_step = 5e-5;           // [m] driver step during the fit (>= element.max_step)
  // Polish the coarse-step optimum with a few iterations at the fine step (false: only where the
  // two steps' combined NRMSE differ by more than 1 %; otherwise the optimum and its Jacobian
  // stay at the fitting step, the NRMSE and BIC being still evaluated at the fine step).
  bool polish = true;
  double loss_scale = 0.1;          // soft-L1 scale c, fraction of the range; 0: plain least squares
  int max_iterations = 40;          // Levenberg-Marquardt iterations
  int threads = 2;                  // finite-difference columns evaluated in parallel
  int starts = 1;                   // 2: also start from the middle of the box (in parallel where threads > 1); best kept
  double fd_step = 2e-3;            // forward-difference step in the [0, 1] parameter space
  // Keep the fitted model's record (CalibrationResult::model) and its row labels
  // (comparison.model_segments.labels). Diagnose, which fits a score of models and reads
  // neither, keeps none: some 40 MB a fit on a 40-cycle record at the fine step.
  bool keep_model = true;
  // Which free parameters get a profile-likelihood interval (FittedParam::profile_lower/upper):
  // none; those whose standard error says little (`poor`: at a bound, not identifiable, or a
  // linearised 95 % interval reaching past a bound); all. Each costs some ten fits of the
  // others at the fitting step.
  enum class Profile { none, poor, all };
  Profile profile = Profile::poor;
  CompareOptions compare;
};

struct FittedParam {
  std::string name;   // "ks", "rate_and_state.a"
  std::string owner;  // the law or the effect
  Dimension dim = Dimension::dimensionless;
  bool free = false;
  bool log_scale = false;
  double start = 0.0, value = 0.0;  // [SI]
  double lower = 0.0, upper = 0.0;  // bounds used [SI]
  double se = 0.0;                  // standard error [SI]; inf: not identifiable from this record
  bool at_bound = false;
  // Profile-likelihood 95 % interval [SI] (CalibrationOptions::profile); NaN: not profiled. An
  // open end is a bound the profile reached inside the criterion: the record does not pin the
  // parameter down on that side.
  double profile_lower = std::numeric_limits<double>::quiet_NaN(), profile_upper = std::numeric_limits<double>::quiet_NaN();
  bool profile_lower_open = false, profile_upper_open = false;
  int profile_fits = 0;
  bool profiled() const { return profile_lower == profile_lower; }  // not NaN
};

struct CalibrationResult {
  std::string law;
  std::vector<std::string> effects;
  std::vector<FittedParam> params;  // every real parameter, law first then effects in order
  // The choices, switches and counts the model ran with ("dilation": "reversible",
  // "directional_wear.bins": 4), given or default: with `params` they rebuild the fitted joint
  // (a case's `[[joints]] calibration = "fit.json"`).
  nlohmann::json settings = nlohmann::json::object();
  std::string status;               // "converged", "iteration limit", "failed"
  bool converged = false;
  int iterations = 0;
  long evaluations = 0;             // element-driver runs
  // The fitted model's run at the fine step: its increments (sub-steps included) and those that
  // missed the stage's normal condition (the model joint lifted off, or had no consistent normal
  // stress there): where it missed, its curve is not the joint's answer to the record's path.
  long increments = 0, missed_increments = 0;
  std::array<double, 3> nrmse{};    // shear stress, normal displacement, combined (fine step)
  std::array<double, 3> nrmse_fit{};  // the same at the fitting step
  double rss = 0.0;                 // sum of squared range-normalised residuals (fine step)
  std::size_t n = 0;                // compared residuals (both variables)
  int k = 0;                        // free parameters
  double bic = 0.0;                 // n ln(RSS/n) + k ln(n)
  std::vector<std::string> warnings;
  Comparison comparison;            // at the fine step
  MeasurementFile model;            // the fitted model's record (fine step)
  std::string model_description;
  double wall_ms = 0.0;

  double value(const std::string& name) const;  // a parameter's value; throws if unknown
};

// The shear path of each stage of a record as element-driver stages: constant normal stress at
// the stage's median, the measured shear displacement against time from the stage's first row.
std::vector<ElementStage> stages_from_data(const MeasurementFile& data, const Segmentation& seg);

// Starting-value estimates from a record (SI; angles in rad). Each is taken on the first forward
// stroke of every stage with shear motion and averaged over those stages.
struct DataEstimates {
  double ks = 0.0;                 // initial slope of shear stress over shear displacement [Pa/m]
  double peak_friction = 0.0;      // atan(max |tau| / sigma_n)
  double residual_friction = 0.0;  // atan(|tau| / sigma_n) over the last tenth of the stroke
  double mean_friction = 0.0;      // atan(mean |tau| / sigma_n) past the peak
  double dilation_angle = 0.0;     // atan of the mean normal-displacement slope past the peak
  double peak_disp = 0.0;          // offset of the peak [m]
  double softening_disp = 0.0;     // plastic offset over which the strength falls half-way to residual [m]
  double mean_normal_stress = 0.0; // [Pa]
};
DataEstimates estimate_from_data(const MeasurementFile& data, const Segmentation& seg);

// Fits; throws InputError for unknown laws, effects or parameter names (listing the valid ones)
// and for bad fixed values. A fit that fails or stops early is reported in `status`/`warnings`.
CalibrationResult calibrate(const MeasurementFile& data, const Segmentation& seg, const CalibrationOptions& options);

nlohmann::json to_json(const CalibrationResult& r);
std::string format_table(const CalibrationResult& r);

}  // namespace rockdem
