#include "framework/analysis/calibration_fit.hpp"

#include <algorithm>
#include <cstdio>
#include <thread>

namespace rockdem::calibration_detail {
namespace {

RawValue raw_of(double v, Dimension d) {
  RawValue r;
  if (d == Dimension::dimensionless) {
    r.value = v;
  } else {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.17g %s", v, std::string(si_unit(d)).c_str());
    r.value = std::string(buf);
  }
  r.where = "calibration";
  return r;
}

}  // namespace

bool log_dimension(Dimension d) {
  return d == Dimension::stiffness || d == Dimension::length || d == Dimension::stress ||
         d == Dimension::energy_per_area || d == Dimension::velocity;
}

std::pair<double, double> physical_range(Dimension d) {
  switch (d) {
    case Dimension::stiffness: return {1e8, 1e13};        // 0.1 GPa/m .. 10 000 GPa/m
    case Dimension::angle: return {0.0, 80.0 * kDeg};
    case Dimension::length: return {1e-6, 1.0};
    case Dimension::stress: return {1e4, 1e10};
    case Dimension::energy_per_area: return {1.0, 1e9};
    case Dimension::velocity: return {1e-9, 10.0};
    default: return {-100.0, 100.0};
  }
}

Evaluator::Evaluator(const MeasurementFile& data, const Segmentation& seg, const CalibrationOptions& opt,
                     std::vector<Slot> slots, std::vector<std::size_t> free, std::vector<ElementStage> stages)
    : data_(data), seg_(seg), opt_(opt), slots_(std::move(slots)), free_(std::move(free)), stages_(std::move(stages)) {
  for (std::size_t v = 0; v < 2; ++v) {
    double lo = kInf, hi = -kInf;
    for (const auto& r : data_.rows) {
      lo = std::min(lo, compared_value(r, v));
      hi = std::max(hi, compared_value(r, v));
    }
    range_[v] = data_.rows.empty() ? 0.0 : hi - lo;
  }
}

std::unique_ptr<JointModel> Evaluator::build(const std::vector<double>& v) const {
  RawValues law = opt_.law_values;
  std::vector<EffectSpec> effects(opt_.effects.size());
  for (std::size_t e = 0; e < effects.size(); ++e) {
    effects[e].name = opt_.effects[e];
    effects[e].where = "calibration";
    if (auto it = opt_.effect_values.find(opt_.effects[e]); it != opt_.effect_values.end()) effects[e].params = it->second;
  }
  for (std::size_t i = 0; i < slots_.size(); ++i) {
    const Slot& s = slots_[i];
    if (std::isinf(v[i])) continue;  // only defaults are infinite: leave them out
    RawValues& target = s.effect < 0 ? law : effects[static_cast<std::size_t>(s.effect)].params;
    target[s.info.name] = raw_of(v[i], s.info.dim);
  }
  return make_joint_model(opt_.law, law, effects, "calibration");
}

MeasurementFile Evaluator::run(const JointModel& model, double step) const {
  ElementOptions eo = opt_.element;
  eo.max_step = step;
  eo.output_every = 1;
  ElementDriver driver(model, eo);
  ++evaluations_;
  return driver.run(stages_);
}

bool Evaluator::residuals(const double* x, double step, std::vector<double>& r, Comparison* out,
                          MeasurementFile* record, std::string* why) const {
  try {
    const auto model = build(values(x));
    MeasurementFile rec = run(*model, step);
    Comparison c = compare(data_, seg_, rec, opt_.compare);
    r.clear();
    r.reserve(n());
    for (std::size_t v = 0; v < 2; ++v) {
      if (!(range_[v] > 0.0)) continue;
      for (std::size_t i = 0; i < data_.rows.size(); ++i) {
        const double d = (c.alignment.model[v][i] - compared_value(data_.rows[i], v)) / range_[v];
        r.push_back(std::isfinite(d) ? d : 10.0);
      }
    }
    if (out) *out = std::move(c);
    if (record) *record = std::move(rec);
    return true;
  } catch (const std::exception& e) {
    if (why) *why = e.what();
    return false;
  }
}

bool Evaluator::jacobian(const double* x, const std::vector<double>& r0, double step, Eigen::MatrixXd& J) const {
  const std::size_t kk = k(), nn = r0.size();
  J.setZero(static_cast<Eigen::Index>(nn), static_cast<Eigen::Index>(kk));
  std::atomic<std::size_t> next{0};
  auto work = [&] {
    std::vector<double> xp(x, x + kk), r;
    for (std::size_t j = next++; j < kk; j = next++) {
      // Forward step (backward at the upper bound); where the model cannot run there, the
      // other side; where neither runs, the column stays zero (no usable sensitivity) rather
      // than failing the whole step.
      double h = xp[j] + opt_.fd_step <= 1.0 ? opt_.fd_step : -opt_.fd_step;
      xp[j] = x[j] + h;
      bool got = residuals(xp.data(), step, r) && r.size() == nn;
      if (!got && x[j] - h >= 0.0 && x[j] - h <= 1.0) {
        h = -h;
        xp[j] = x[j] + h;
        got = residuals(xp.data(), step, r) && r.size() == nn;
      }
      if (got) {
        for (std::size_t i = 0; i < nn; ++i)
          J(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = (r[i] - r0[i]) / h;
      }
      xp[j] = x[j];
    }
  };
  const std::size_t nt = std::min<std::size_t>(static_cast<std::size_t>(std::max(1, opt_.threads)), kk);
  std::vector<std::thread> pool;
  for (std::size_t t = 1; t < nt; ++t) pool.emplace_back(work);
  work();
  for (auto& t : pool) t.join();
  return true;
}

}  // namespace rockdem::calibration_detail
