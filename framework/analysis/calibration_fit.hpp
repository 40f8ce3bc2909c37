#pragma once
// The fit behind calibrate() (framework/analysis/calibration.hpp), shared by the files that make
// it up: the parameters as slots with their bounds and [0, 1] maps, the residuals of a model
// against the record, their forward-difference Jacobian and the Ceres cost that reads them.
// Internal to the analysis layer.
#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <memory>
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

  std::unique_ptr<JointModel> build(const std::vector<double>& v) const;
  MeasurementFile run(const JointModel& model, double step) const;
  // Range-normalised residuals (model - measured) of every compared row; false if the model
  // cannot be built or run, or its record cannot be compared.
  bool residuals(const double* x, double step, std::vector<double>& r, Comparison* out = nullptr,
                 MeasurementFile* record = nullptr, std::string* why = nullptr) const;
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
};

// Residuals and Jacobian at the last point Ceres asked for, shared by the one-residual blocks
// (one block per residual, so that the robust loss acts on each residual, not on their sum).
class SharedResiduals {
 public:
  SharedResiduals(const Evaluator& ev, double step) : ev_(ev), step_(step) {}
  bool at(const double* x, bool need_jacobian) {
    const std::size_t kk = ev_.k();
    if (!(have_ && std::equal(x, x + kk, x_.begin()))) {
      x_.assign(x, x + kk);
      have_ = true;
      have_j_ = false;
      ok_ = ev_.residuals(x, step_, r_);
    }
    if (ok_ && need_jacobian && !have_j_) {
      ok_j_ = ev_.jacobian(x, r_, step_, J_);
      have_j_ = true;
    }
    return ok_ && (!need_jacobian || ok_j_);
  }
  double r(std::size_t i) const { return r_[i]; }
  double j(std::size_t i, std::size_t c) const {
    return J_(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(c));
  }

 private:
  const Evaluator& ev_;
  double step_;
  std::vector<double> x_, r_;
  Eigen::MatrixXd J_;
  bool have_ = false, have_j_ = false, ok_ = false, ok_j_ = false;
};

class RowCost final : public ceres::CostFunction {
 public:
  RowCost(SharedResiduals& s, std::size_t row, int k) : s_(s), row_(row) {
    set_num_residuals(1);
    mutable_parameter_block_sizes()->push_back(k);
  }
  bool Evaluate(double const* const* p, double* residuals, double** jacobians) const override {
    const bool need_j = jacobians != nullptr && jacobians[0] != nullptr;
    if (!s_.at(p[0], need_j)) return false;
    residuals[0] = s_.r(row_);
    if (need_j) {
      const auto kk = static_cast<std::size_t>(parameter_block_sizes()[0]);
      for (std::size_t c = 0; c < kk; ++c) jacobians[0][c] = s_.j(row_, c);
    }
    return true;
  }

 private:
  SharedResiduals& s_;
  std::size_t row_;
};

}  // namespace rockdem::calibration_detail
