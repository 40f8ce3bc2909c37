#pragma once
// The fit behind calibrate() (framework/analysis/calibration.hpp), shared by the files that make
// it up: the parameters as slots with their bounds and [0, 1] maps, the residuals of a model
// against the record, their forward-difference Jacobian, the Ceres solve (calibration_fit.cpp)
// and the standard errors; the slots' starting values (calibration_start.cpp). Internal to the
// analysis layer.
#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <map>
#include <memory>
#include <mutex>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include <ceres/ceres.h>
#include <Eigen/Dense>

#include "framework/analysis/calibration.hpp"
#include "framework/plugin_api/joint_law.hpp"

namespace rockdem::calibration_detail {

constexpr double kDeg = std::numbers::pi / 180.0;

// One real parameter of the law or of an effect.
struct Slot {
  ParamInfo info;
  std::string name;   // qualified: "ks" or "effect.param"
  std::string owner;  // law or effect name
  int effect = -1;    // index into the effect list, -1: the law
  bool free = false, log_scale = false;
  double lower = 0.0, upper = 0.0, value = 0.0, start = 0.0;
  bool given = false;  // written in law_values/effect_values
};

// Dimensions whose plausible values span decades: their free parameters move on a log scale.
bool log_dimension(Dimension d);

// Physical ranges where the registry's are infinite or wider than any rock joint needs.
std::pair<double, double> physical_range(Dimension d);

// The residual machinery shared by the fit, the Jacobian and the final evaluation.
class Evaluator {
 public:
  Evaluator(const MeasurementFile& data, const Segmentation& seg, const CalibrationOptions& opt,
            std::vector<Slot> slots, std::vector<std::size_t> free, std::vector<ElementStage> stages);

  std::size_t k() const { return free_.size(); }
  std::size_t n() const {
    std::size_t n = 0;
    for (std::size_t v = 0; v < 2; ++v)
      if (range_[v] > 0.0) n += data_.rows.size();
    return n;
  }
  const std::vector<Slot>& slots() const { return slots_; }
  const std::vector<std::size_t>& free() const { return free_; }
  long evaluations() const { return evaluations_.load(); }
  long placement_hits() const { return placement_hits_.load(); }  // runs that reused a placement (below)

  double to_si(std::size_t j, double x) const {
    const Slot& s = slots_[free_[j]];
    x = std::clamp(x, 0.0, 1.0);
    return s.log_scale ? std::exp(std::log(s.lower) + x * (std::log(s.upper) - std::log(s.lower)))
                       : s.lower + x * (s.upper - s.lower);
  }
  double to_unit(std::size_t j, double v) const {
    const Slot& s = slots_[free_[j]];
    const double x = s.log_scale ? (std::log(v) - std::log(s.lower)) / (std::log(s.upper) - std::log(s.lower))
                                 : (v - s.lower) / (s.upper - s.lower);
    return std::clamp(x, 0.0, 1.0);
  }
  double dsi_dx(std::size_t j, double x) const {
    const Slot& s = slots_[free_[j]];
    return s.log_scale ? to_si(j, x) * (std::log(s.upper) - std::log(s.lower)) : s.upper - s.lower;
  }

  std::vector<double> values(const double* x) const {
    std::vector<double> v(slots_.size());
    for (std::size_t i = 0; i < slots_.size(); ++i) v[i] = slots_[i].value;
    for (std::size_t j = 0; j < free_.size(); ++j) v[free_[j]] = to_si(j, x[j]);
    return v;
  }

  // "friction = 36.2 deg, ks = 12 GPa/m, ..." for the free parameters at x: a failure names the
  // point it failed at, so that a user can see which corner of the bounds the model cannot run in.
  std::string describe(const double* x) const;

  std::unique_ptr<JointModel> build(const std::vector<double>& v) const;
  // The element driver's increments in a run and those that missed the stage's normal
  // condition (ElementDriver::unconverged_steps).
  struct Misses {
    long missed = 0, increments = 0;
  };
  // `extra`: also the record's extra columns (dilation, dissipated energy), which residuals
  // do not read (one allocation per row).
  MeasurementFile run(const JointModel& model, double step, Misses* misses = nullptr, bool extra = true) const;
  // Range-normalised residuals (model - measured) of every compared row; false if the model
  // cannot be built or run, or its record cannot be compared.
  bool residuals(const double* x, double step, std::vector<double>& r, Comparison* out = nullptr,
                 MeasurementFile* record = nullptr, std::string* why = nullptr, Misses* misses = nullptr) const;
  // Forward-difference Jacobian in the [0, 1] space, columns in parallel.
  bool jacobian(const double* x, const std::vector<double>& r0, double step, Eigen::MatrixXd& J) const;

 private:
  const MeasurementFile& data_;
  const Segmentation& seg_;
  const CalibrationOptions& opt_;
  std::vector<Slot> slots_;
  std::vector<std::size_t> free_;
  std::vector<ElementStage> stages_;
  std::array<double, 2> range_{};
  mutable std::atomic<long> evaluations_{0};
  // Where align() placed the measured rows on the last record of each driver step, and the path
  // columns that placing read (stage, time, shear displacement): every run at one step follows
  // the same prescribed path, so the segmentation and alignment, a tenth of a fit's time, are
  // reused while those columns are the same to the bit (the alignment is then the same too). The
  // normal stress, which the segmentation also reads but only to check each stage's median
  // against the measurement's, is checked again on every run.
  // Where the path itself follows the parameters (a loading frame's compliance), no run matches
  // another: after a few misses without a hit nothing is kept or looked up any more.
  struct Placement {
    double step = 0.0;
    std::vector<int> stage;
    std::vector<double> time, shear;  // the path columns, as read
    std::vector<StageInfo> stages;    // the model record's
    std::vector<AlignedRow> rows;
  };
  std::shared_ptr<const Placement> placement(double step, const MeasurementFile& rec) const;
  void remember(double step, const MeasurementFile& rec, const Comparison& c) const;
  bool placing_pays() const { return placement_hits_.load() > 0 || placement_misses_.load() < 4; }
  mutable std::mutex placements_mutex_;
  mutable std::vector<std::shared_ptr<const Placement>> placements_;  // one per step, newest first
  mutable std::atomic<long> placement_hits_{0}, placement_misses_{0};
};

// Bounds (the registry's tightened to physical ones), scales and starting values of every
// parameter: warm start > written values > estimates from the data > defaults
// (calibration_start.cpp). InputError for a parameter that has none.
void set_bounds_and_starts(std::vector<Slot>& slots, const MeasurementFile& data, const Segmentation& seg,
                           const CalibrationOptions& options, const std::map<std::string, double>& fix,
                           std::vector<std::string>& warnings);

// Bounded Levenberg-Marquardt in the [0, 1] space from x (updated to the optimum) at the given
// driver step, one residual block per compared row under the soft-L1 loss (loss_scale 0: plain
// least squares); adds the iterations it took. The Jacobian is taken at `jacobian_step` (0: the
// driver step): the fine-step polish takes it at the fitting step, so that each of
// its iterations costs one fine run and k + 1 runs at the fitting step instead of k + 1 fine ones.
// Every step is still accepted on the residuals at `step`, so the polish converges to where the
// fine step's cost is stationary along the fitting step's sensitivities. Such a polish (a
// jacobian_step coarser than `step`) starts from a trust-region radius of 1, not Ceres's 1e4, and
// so does a fit whose start is an optimum already (`near_optimum`).
// `fixed` >= 0 holds that parameter at its value in x (a profile's fits).
ceres::Solver::Summary solve(const Evaluator& ev, std::vector<double>& x, double step, int max_iterations, double loss_scale,
                             std::atomic<int>& iterations, double jacobian_step = 0.0, bool near_optimum = false,
                             int fixed = -1);

// The fit's objective at residuals r: half the sum of Ceres's soft-L1 loss of scale c (plain
// squares where c = 0).
double robust_cost(const std::vector<double>& r, double c);

// Profile-likelihood 95 % interval of free parameter j in the [0, 1] space, from the optimum x at
// the driver step `step`: parameter j is held at values stepped away from x[j] and the others are
// refitted there (warm, from the neighbouring point's optimum); a value is inside while
// n_eff ln(C/C0) <= 3.841 (chi-square, one degree of freedom, 0.95), C the objective, C0 at x,
// n_eff the independent values the residuals are worth (effective_size.hpp). Steps start at two
// linearised standard errors (se_unit; 0.05 where infinite), double until the criterion is
// crossed or the bound is reached, and the crossing is bisected twice and interpolated on sqrt(LR).
struct ProfileEnd {
  double u = 0.0;     // [0, 1]
  bool open = true;   // the bound was reached inside the criterion
};
struct ProfileInterval {
  bool ran = true;  // false: no profile (why says why): the model does not run at the optimum, or fits it exactly
  std::string why;
  ProfileEnd lower, upper;
  int fits = 0;
  // The lowest objective met, as a fraction of the optimum's (below 1: the fit stopped in a local
  // optimum, or the fine-step polish moved it), and the parameter's value there.
  double lowest = 1.0, lowest_at = 0.0;
  std::vector<double> lowest_x;  // every free parameter there (empty: none lower)
};
// J: the Jacobian at x at `step` (the profile trace's; empty: none, each refit starts from the
// neighbouring point), taken once for every parameter profiled.
ProfileInterval profile_interval(const Evaluator& ev, const std::vector<double>& x, const Eigen::MatrixXd& J, std::size_t j,
                                 double step, double n_eff, double se_unit, double loss_scale);

// Standard errors in the [0, 1] space from the Jacobian at the optimum x (residuals r at the
// driver step): Cov = (J^T J)^-1 s^2, s^2 =
// RSS/(n - k) from `res`; infinite where the record does not constrain the parameter, all
// infinite (and a warning in `res`) if the Jacobian fails.
Eigen::VectorXd unit_standard_errors(const Evaluator& ev, const std::vector<double>& x, const std::vector<double>& r,
                                     double step, CalibrationResult& res);

}  // namespace rockdem::calibration_detail
