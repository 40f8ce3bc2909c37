#include "framework/analysis/calibration.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <mutex>
#include <numbers>
#include <optional>
#include <set>
#include <sstream>
#include <thread>

#include <ceres/ceres.h>
#include <glog/logging.h>
#include <Eigen/Dense>

#include "framework/core/error.hpp"
#include "framework/lab/lab_case.hpp"
#include "framework/io/toml_values.hpp"
#include "framework/plugin_api/joint_law.hpp"

namespace rockdem {
namespace {

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

bool log_dimension(Dimension d) {
  return d == Dimension::stiffness || d == Dimension::length || d == Dimension::stress ||
         d == Dimension::energy_per_area || d == Dimension::velocity;
}

// Physical ranges where the registry's are infinite or wider than any rock joint needs.
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

std::string join(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& x : v) s += (s.empty() ? "" : ", ") + x;
  return s;
}

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

double median_of(std::vector<double> v) {
  if (v.empty()) return 0.0;
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

std::string meta(const MeasurementFile& f, const std::string& key) {
  for (const auto& [k, v] : f.metadata)
    if (k == key) return v;
  return {};
}

// The residual machinery shared by the fit, the Jacobian and the final evaluation.
class Evaluator {
 public:
  Evaluator(const MeasurementFile& data, const Segmentation& seg, const CalibrationOptions& opt,
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

  std::unique_ptr<JointModel> build(const std::vector<double>& v) const {
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

  MeasurementFile run(const JointModel& model, double step) const {
    ElementOptions eo = opt_.element;
    eo.max_step = step;
    eo.output_every = 1;
    ElementDriver driver(model, eo);
    ++evaluations_;
    return driver.run(stages_);
  }

  // Range-normalised residuals (model - measured) of every compared row; false if the model
  // cannot be built or run, or its record cannot be compared.
  bool residuals(const double* x, double step, std::vector<double>& r, Comparison* out = nullptr,
                 MeasurementFile* record = nullptr, std::string* why = nullptr) const {
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

  // Forward-difference Jacobian in the [0, 1] space, columns in parallel.
  bool jacobian(const double* x, const std::vector<double>& r0, double step, Eigen::MatrixXd& J) const {
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

std::array<double, 3> nrmse_of(const Comparison& c) {
  return {c.overall.var[0].nrmse, c.overall.var[1].nrmse, c.combined_nrmse};
}

}  // namespace

double CalibrationResult::value(const std::string& name) const {
  for (const auto& p : params)
    if (p.name == name) return p.value;
  throw InputError("calibration result: no parameter '" + name + "'");
}

std::vector<ElementStage> stages_from_data(const MeasurementFile& data, const Segmentation& seg) {
  std::vector<ElementStage> out;
  for (const auto& st : seg.stages) {
    ElementStage s;
    s.normal_stress = st.normal_stress_MPa * 1e6;
    s.control = NormalControl::constant_stress;
    std::vector<double> t, u;
    const double t0 = data.rows[st.begin].time_s;
    for (std::size_t i = st.begin; i < st.end; ++i) {
      t.push_back(data.rows[i].time_s - t0);
      u.push_back(data.rows[i].shear_disp_mm * 1e-3);
    }
    s.path = ShearPath::table(std::move(t), std::move(u));
    out.push_back(std::move(s));
  }
  return out;
}

DataEstimates estimate_from_data(const MeasurementFile& data, const Segmentation& seg) {
  DataEstimates e;
  std::vector<double> ks, peak, resid, mean, dil, upk, usoft, sig;
  for (const auto& st : seg.stages) {
    if (st.segment_count == 0) continue;
    const Segment& g = seg.segments[st.first_segment];
    if (g.motion == 0 || g.end <= g.curve_begin + 3) continue;
    const double sn = std::max(st.normal_stress_MPa, 1e-6);
    const double s = g.motion;
    const std::size_t b = g.curve_begin, en = g.end;
    const double u0 = data.rows[b].shear_disp_mm;
    std::size_t ip = b;
    for (std::size_t i = b; i < en; ++i)
      if (s * data.rows[i].shear_stress_MPa > s * data.rows[ip].shear_stress_MPa) ip = i;
    const double tp = s * data.rows[ip].shear_stress_MPa;
    // Initial slope: least squares through the rows below 60 % of the peak before it.
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    int m = 0;
    for (std::size_t i = b; i <= ip; ++i) {
      const double y = s * data.rows[i].shear_stress_MPa;
      if (y >= 0.6 * tp && m >= 2) break;
      const double x = s * (data.rows[i].shear_disp_mm - u0);
      sx += x, sy += y, sxx += x * x, sxy += x * y, ++m;
      if (y >= 0.6 * tp) break;
    }
    const double den = m * sxx - sx * sx;
    if (m >= 2 && den > 0.0) ks.push_back((m * sxy - sx * sy) / den * 1e9);  // MPa/mm -> Pa/m
    peak.push_back(std::atan(tp / sn));
    const std::size_t n = en - b, tail = std::max<std::size_t>(1, n / 10);
    double r = 0.0, mt = 0.0;
    for (std::size_t i = en - tail; i < en; ++i) r += s * data.rows[i].shear_stress_MPa;
    r /= static_cast<double>(tail);
    resid.push_back(std::atan(std::max(r, 0.0) / sn));
    for (std::size_t i = ip; i < en; ++i) mt += s * data.rows[i].shear_stress_MPa;
    mean.push_back(std::atan(std::max(mt / static_cast<double>(en - ip), 0.0) / sn));
    const double du = std::abs(data.rows[en - 1].shear_disp_mm - data.rows[ip].shear_disp_mm);
    if (du > 0.0) dil.push_back(std::atan(std::max(0.0, (data.rows[en - 1].normal_disp_mm - data.rows[ip].normal_disp_mm) / du)));
    upk.push_back(std::abs(data.rows[ip].shear_disp_mm - u0) * 1e-3);
    double soft = std::abs(data.rows[en - 1].shear_disp_mm - data.rows[ip].shear_disp_mm) * 0.5;
    for (std::size_t i = ip; i < en; ++i) {
      if (s * data.rows[i].shear_stress_MPa <= 0.5 * (tp + r)) {
        soft = std::abs(data.rows[i].shear_disp_mm - data.rows[ip].shear_disp_mm);
        break;
      }
    }
    usoft.push_back(std::max(soft, 1e-3) * 1e-3);
    sig.push_back(sn * 1e6);
  }
  auto avg = [](const std::vector<double>& v, double fallback) {
    if (v.empty()) return fallback;
    double a = 0.0;
    for (double x : v) a += x;
    return a / static_cast<double>(v.size());
  };
  e.ks = ks.empty() ? 1e10 : median_of(ks);
  e.peak_friction = avg(peak, 35 * kDeg);
  e.residual_friction = avg(resid, 30 * kDeg);
  e.mean_friction = avg(mean, 32 * kDeg);
  e.dilation_angle = avg(dil, 2 * kDeg);
  e.peak_disp = avg(upk, 1e-3);
  e.softening_disp = avg(usoft, 5e-3);
  e.mean_normal_stress = avg(sig, 1e6);
  return e;
}

CalibrationResult calibrate(const MeasurementFile& data, const Segmentation& seg, const CalibrationOptions& options) {
  // Ceres logs through glog to stderr; failed trial steps are expected here and reported in the
  // result, so only fatal messages may pass (a library setting, made once).
  static std::once_flag quiet_glog;
  std::call_once(quiet_glog, [] { FLAGS_minloglevel = google::GLOG_FATAL; });
  const auto t0 = std::chrono::steady_clock::now();
  const auto& law_entry = JointLawRegistry::instance().get(options.law, "joint law", "calibrate --law");
  CalibrationResult res;
  res.law = options.law;
  res.effects = options.effects;

  // The real parameters of the law and its effects.
  std::vector<Slot> slots;
  // Free unless the law or effect declares the parameter fixed by default (what a shear record
  // cannot identify); freed or fixed below as asked.
  auto add_slots = [&](const std::vector<ParamInfo>& infos, const std::vector<std::string>& fixed, const std::string& owner,
                       int effect, const RawValues& given) {
    for (const auto& info : infos) {
      if (info.kind != "real") continue;
      Slot s;
      s.info = info;
      s.owner = owner;
      s.effect = effect;
      s.name = effect < 0 ? info.name : owner + "." + info.name;
      s.free = std::find(fixed.begin(), fixed.end(), info.name) == fixed.end();
      if (auto it = given.find(info.name); it != given.end()) {
        s.value = parse_real(info, it->second, (effect < 0 ? "joint law '" : "effect '") + owner + "'");
        s.given = true;
      } else {
        s.value = info.default_real.value_or(std::nan(""));
      }
      slots.push_back(std::move(s));
    }
  };
  add_slots(law_entry.params, law_entry.declared.fixed_by_default, options.law, -1, options.law_values);
  for (std::size_t e = 0; e < options.effects.size(); ++e) {
    const auto& ee = EffectRegistry::instance().get(options.effects[e], "effect", "calibrate --effects");
    const auto it = options.effect_values.find(options.effects[e]);
    add_slots(ee.params, ee.declared.fixed_by_default, options.effects[e], static_cast<int>(e),
              it == options.effect_values.end() ? RawValues{} : it->second);
  }
  auto names = [&] {
    std::vector<std::string> v;
    for (const auto& s : slots) v.push_back(s.name);
    return join(v);
  };
  auto find = [&](const std::string& name, const std::string& what) -> Slot& {
    Slot* hit = nullptr;
    int matches = 0;
    for (auto& s : slots) {
      if (s.name == name) return s;
      if (s.effect >= 0 && s.info.name == name) hit = &s, ++matches;
    }
    if (matches == 1) return *hit;
    throw InputError(what + ": unknown parameter '" + name + "'" +
                     (matches > 1 ? " (several effects have it: write effect.param)" : "") +
                     "; real parameters of " + options.law +
                     (options.effects.empty() ? "" : " + " + join(options.effects)) + ": " + names());
  };

  // Which are free: real parameters not fixed by default (or freed), not fixed by the user.
  for (const auto& n : options.free) find(n, "--free").free = true;
  if (!options.only_free.empty()) {
    std::set<std::string> keep;
    for (const auto& n : options.only_free) keep.insert(find(n, "calibration").name);
    for (auto& s : slots) s.free = s.free && keep.count(s.name) > 0;
  }
  std::map<std::string, double> fix = options.fix;
  for (const auto& [n, text] : options.fix_text) {
    const Slot& s = find(n, "--fix");
    RawValue raw;
    raw.where = "--fix " + n + "=" + text;
    char* end = nullptr;
    const double num = std::strtod(text.c_str(), &end);
    if (end != text.c_str() && *end == '\0') raw.value = num;
    else raw.value = text;
    fix[s.name] = parse_real(s.info, raw, (s.effect < 0 ? "joint law '" : "effect '") + s.owner + "'");
  }
  for (const auto& [n, v] : fix) {
    Slot& s = find(n, "--fix");
    check_range(s.info, v, "--fix " + n, s.owner);
    s.value = v;
    s.free = false;
    s.given = true;
  }

  // Starting values: warm start > written values > estimates from the data > defaults.
  const DataEstimates est = estimate_from_data(data, seg);
  const bool has_initial_friction = std::any_of(slots.begin(), slots.end(), [](const Slot& s) { return s.name == "initial_friction"; });
  auto slot_value = [&](const std::string& n, double fallback) {
    for (const auto& s : slots)
      if (s.name == n && std::isfinite(s.value)) return s.value;
    return fallback;
  };
  auto estimate = [&](const Slot& s) -> std::optional<double> {
    if (s.effect >= 0) return std::nullopt;
    const std::string& n = s.name;
    if (n == "ks") return est.ks;
    if (n == "kn") return 10.0 * est.ks;
    if (n == "friction") return has_initial_friction ? est.residual_friction : est.mean_friction;
    if (n == "initial_friction") return est.peak_friction + 2.0 * kDeg;
    if (n == "residual_friction") return est.residual_friction;
    if (n == "dilation_angle") return est.dilation_angle;
    if (n == "roughness") return est.softening_disp / std::numbers::ln2;
    if (n == "jcs") return 100e6;
    if (n == "lab_length") {
      const std::string l = meta(data, "joint_length_m");
      return l.empty() ? 0.1 : std::stod(l);
    }
    if (n == "jrc") {
      const double jcs = slot_value("jcs", 100e6);
      const double lg = std::log10(std::max(jcs / est.mean_normal_stress, 1.5));
      return std::clamp((est.peak_friction - est.residual_friction) / kDeg / lg, 0.5, 19.5);
    }
    return std::nullopt;
  };
  for (auto& s : slots) {
    const auto [plo, phi] = physical_range(s.info.dim);
    s.lower = std::max(s.info.min, plo);
    s.upper = std::min(s.info.max, phi);
    if (s.info.min_open) s.lower = std::max(s.lower, s.info.min + 1e-9 * std::max(1.0, std::abs(s.info.min)));
    if (s.info.max_open) s.upper = std::min(s.upper, s.info.max - 1e-9 * std::max(1.0, std::abs(s.info.max)));
    s.log_scale = log_dimension(s.info.dim) && s.lower > 0.0;
    auto ws = options.start.find(s.name);
    if (ws != options.start.end() && !fix.count(s.name)) {
      s.value = ws->second;
    } else if (!s.given) {
      if (auto v = estimate(s); v && (s.free || !std::isfinite(s.value))) s.value = *v;
    }
    if (!std::isfinite(s.value) && s.free) s.value = s.log_scale ? std::sqrt(s.lower * s.upper) : 0.5 * (s.lower + s.upper);
    if (std::isnan(s.value)) {
      throw InputError("calibrate: parameter '" + s.name + "' has no default and cannot be estimated from the data; "
                       "give it with --fix " + s.name + "=VALUE or a --case");
    }
    if (s.free) s.value = std::clamp(s.value, s.lower, s.upper);
    s.start = s.value;
  }
  if (est.ks <= 0.0) res.warnings.push_back("no initial elastic slope found in the record; ks starts from a default");

  std::vector<std::size_t> free;
  for (std::size_t i = 0; i < slots.size(); ++i)
    if (slots[i].free) free.push_back(i);
  std::vector<ElementStage> stages = options.stages.empty() ? stages_from_data(data, seg) : options.stages;
  const double fine = options.element.max_step;
  // A long path (40 dynamic cycles: 2 m of travel) at the fitting step would cost 40 000
  // increments a run; the fitting step grows so that a run has at most kMaxFitIncrements.
  constexpr double kMaxFitIncrements = 20000.0;
  double travel = 0.0;
  for (const auto& st : stages) {
    if (st.path.kind == ShearPath::Kind::table) {
      for (std::size_t i = 1; i < st.path.disp.size(); ++i) travel += std::abs(st.path.disp[i] - st.path.disp[i - 1]);
    } else {
      const double per_cycle = (st.path.one_sided ? 2.0 : 4.0) * st.path.amplitude;
      travel += per_cycle * st.path.count;
    }
  }
  const double coarse = std::max({options.fit_step, fine, travel / kMaxFitIncrements});
  Evaluator ev(data, seg, options, slots, free, stages);
  const std::size_t kk = free.size();
  std::vector<double> x(kk);
  // Start a little inside the bounds: a default on a bound (an effect's "off" value) is a poor
  // start for a bounded trust-region step.
  for (std::size_t j = 0; j < kk; ++j) x[j] = std::clamp(ev.to_unit(j, slots[free[j]].value), 0.02, 0.98);

  // The starting point must run. Estimates can be absurd for a law (a first-stroke dilation
  // angle accumulated monotonically over 40 cycles lifts the joint off), so the registry defaults,
  // then the lower bounds, of the free parameters are tried before giving up: a model that
  // cannot be run at all is the user's input error.
  {
    std::vector<double> r;
    std::string why;
    bool ok = ev.residuals(x.data(), coarse, r, nullptr, nullptr, &why);
    for (int attempt = 0; !ok && attempt < 2; ++attempt) {
      for (std::size_t j = 0; j < kk; ++j) {
        const Slot& s = slots[free[j]];
        if (attempt == 0 && s.info.default_real && std::isfinite(*s.info.default_real) && !options.start.count(s.name)) {
          x[j] = ev.to_unit(j, std::clamp(*s.info.default_real, s.lower, s.upper));
        } else if (attempt == 1 && s.info.dim != Dimension::stiffness && !options.start.count(s.name)) {
          x[j] = 0.0;
        }
      }
      ok = ev.residuals(x.data(), coarse, r);
      if (ok) res.warnings.push_back(std::string("the data estimates could not be run; the fit started from the ") +
                                     (attempt == 0 ? "registry defaults" : "lower bounds") + " of the free parameters");
    }
    if (!ok) throw InputError("calibrate: the model at the starting values cannot be run or compared with the data: " + why);
    for (std::size_t j = 0; j < kk; ++j) slots[free[j]].start = ev.to_si(j, x[j]);
  }

  // Levenberg-Marquardt at the coarse step to convergence, then a polish at the fine step from
  // there (a few iterations): rate-sensitive laws (continuously-yielding) shift by a few per cent
  // in their parameters between the two steps even where the NRMSE does not.
  std::atomic<int> iterations{0};
  auto solve_from = [&](std::vector<double>& xs, double step, int max_iterations) {
    SharedResiduals shared(ev, step);
    ceres::Problem::Options po;
    po.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    ceres::Problem problem(po);
    std::unique_ptr<ceres::LossFunction> loss;
    if (options.loss_scale > 0.0) loss = std::make_unique<ceres::SoftLOneLoss>(options.loss_scale);
    const std::size_t nn = ev.n();
    for (std::size_t i = 0; i < nn; ++i)
      problem.AddResidualBlock(new RowCost(shared, i, static_cast<int>(kk)), loss.get(), xs.data());
    for (std::size_t j = 0; j < kk; ++j) {
      problem.SetParameterLowerBound(xs.data(), static_cast<int>(j), 0.0);
      problem.SetParameterUpperBound(xs.data(), static_cast<int>(j), 1.0);
    }
    ceres::Solver::Options so;
    so.minimizer_type = ceres::TRUST_REGION;
    so.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
    so.linear_solver_type = ceres::DENSE_QR;
    so.max_num_iterations = max_iterations;
    so.function_tolerance = 1e-5;
    so.parameter_tolerance = 1e-4;
    so.gradient_tolerance = 1e-8;
    so.num_threads = 1;  // our Jacobian columns run in parallel instead
    so.logging_type = ceres::SILENT;
    so.minimizer_progress_to_stdout = false;
    ceres::Solver::Summary summary;
    ceres::Solve(so, &problem, &summary);
    iterations += static_cast<int>(summary.iterations.size());
    return summary;
  };
  auto solve = [&](double step, int max_iterations) { return solve_from(x, step, max_iterations); };
  bool polished = false;
  if (kk > 0) {
    ceres::Solver::Summary summary;
    if (options.starts < 2) {
      summary = solve(coarse, options.max_iterations);
    } else {
      // A second start in the middle of the [0, 1] box, in parallel: the data estimates can sit
      // in the basin of a poorer minimum (a law bent to make up for what it lacks).
      std::vector<double> x2(kk, 0.5);
      ceres::Solver::Summary s2;
      std::thread other([&] { s2 = solve_from(x2, coarse, options.max_iterations); });
      summary = solve(coarse, options.max_iterations);
      other.join();
      if (s2.termination_type != ceres::FAILURE &&
          (summary.termination_type == ceres::FAILURE || s2.final_cost < summary.final_cost)) {
        x = x2;
        summary = s2;
      }
    }
    // Without `polish`, the fine step is still used where the two steps disagree by more than
    // 1 % in the combined NRMSE (a law or effect sensitive to the step, e.g. at reversals).
    auto steps_disagree = [&] {
      std::vector<double> rc, rf;
      Comparison cc, cf;
      if (!ev.residuals(x.data(), coarse, rc, &cc) || !ev.residuals(x.data(), fine, rf, &cf)) return true;
      return std::abs(cc.combined_nrmse - cf.combined_nrmse) > 0.01 * cf.combined_nrmse;
    };
    if (coarse > fine && summary.termination_type != ceres::FAILURE && (options.polish || steps_disagree())) {
      const ceres::Solver::Summary polish = solve(fine, options.polish ? std::max(3, options.max_iterations / 4) : 4);
      polished = polish.termination_type != ceres::FAILURE;
      if (!polished) res.warnings.push_back("the polish at the fine step failed (" + polish.message + "); the fitting step's optimum is kept");
    }
    switch (summary.termination_type) {
      case ceres::CONVERGENCE: res.status = "converged"; res.converged = true; break;
      case ceres::NO_CONVERGENCE: res.status = "iteration limit"; break;
      default: res.status = "failed"; break;
    }
    if (!res.converged) res.warnings.push_back("fit did not converge (" + res.status + "): " + summary.message);
  } else {
    res.status = "converged";
    res.converged = true;
  }
  res.iterations = iterations.load();

  // Fine-step evaluation, coarse-step NRMSE, Jacobian and standard errors at the optimum.
  std::vector<double> r_fine, r_coarse;
  Comparison c_coarse;
  // Standard errors from the Jacobian at the step of the optimum (fine when polished).
  const bool at_fine = polished || coarse <= fine;
  std::string why_coarse, why_fine;
  const bool coarse_ok = ev.residuals(x.data(), coarse, r_coarse, &c_coarse, &res.model, &why_coarse);
  const bool fine_ok = ev.residuals(x.data(), fine, r_fine, &res.comparison, &res.model, &why_fine);
  if (!coarse_ok && !fine_ok) {
    throw std::runtime_error("calibrate: the fitted model could not be evaluated at the fitting step (" + why_coarse +
                             ") nor at the fine step (" + why_fine + ")");
  }
  if (!coarse_ok) {
    // Seen on test 14 with Continuously-Yielding: at the coarse step the model's record no longer
    // matched the measured path; the fine step is the answer anyway.
    res.warnings.push_back("the fitted model fails at the fitting step (" + why_coarse + "); its errors are those at the fine step");
    r_coarse = r_fine;
    c_coarse = res.comparison;
  }
  if (!fine_ok) {
    res.warnings.push_back("the fitted model fails at the fine step (" + why_fine + "); its errors are those at the fitting step");
    r_fine = r_coarse;
    res.comparison = c_coarse;
  }
  res.nrmse = nrmse_of(res.comparison);
  res.nrmse_fit = nrmse_of(c_coarse);
  res.n = r_fine.size();
  res.k = static_cast<int>(kk);
  for (double v : r_fine) res.rss += v * v;
  const double nd = static_cast<double>(res.n);
  res.bic = nd * std::log(std::max(res.rss, 1e-300) / nd) + static_cast<double>(kk) * std::log(nd);
  if (res.nrmse[2] > 0.0 && std::abs(res.nrmse_fit[2] - res.nrmse[2]) > 0.01 * res.nrmse[2]) {
    char buf[200];
    std::snprintf(buf, sizeof buf, "the fitting step changes the combined NRMSE by more than 1 %% (%.4f at the fit step, %.4f at the fine step)",
                  res.nrmse_fit[2], res.nrmse[2]);
    res.warnings.push_back(buf);
  }
  Eigen::VectorXd se_x = Eigen::VectorXd::Constant(static_cast<Eigen::Index>(kk), kInf);
  if (kk > 0) {
    Eigen::MatrixXd J;
    if (ev.jacobian(x.data(), at_fine ? r_fine : r_coarse, at_fine ? fine : coarse, J)) {
      const Eigen::MatrixXd JtJ = J.transpose() * J;
      const double s2 = res.n > kk ? res.rss / static_cast<double>(res.n - kk) : 0.0;
      Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(JtJ);
      const double lmax = eig.eigenvalues().maxCoeff();
      // Pseudo-inverse: directions the data do not constrain (eigenvalue below 1e-10 of the
      // largest) get an infinite standard error instead of a huge finite one.
      Eigen::VectorXd var = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(kk));
      std::vector<bool> flat(kk, false);
      for (Eigen::Index a = 0; a < static_cast<Eigen::Index>(kk); ++a) {
        const double l = eig.eigenvalues()(a);
        const Eigen::VectorXd v = eig.eigenvectors().col(a);
        if (!(l > 1e-10 * lmax) || !(lmax > 0.0)) {
          for (Eigen::Index j = 0; j < static_cast<Eigen::Index>(kk); ++j)
            if (std::abs(v(j)) > 0.1) flat[static_cast<std::size_t>(j)] = true;
          continue;
        }
        var += v.cwiseProduct(v) / l;
      }
      for (std::size_t j = 0; j < kk; ++j)
        se_x(static_cast<Eigen::Index>(j)) = flat[j] ? kInf : std::sqrt(s2 * var(static_cast<Eigen::Index>(j)));
    } else {
      res.warnings.push_back("the Jacobian at the optimum could not be evaluated: no standard errors");
    }
  }
  const auto vals = ev.values(x.data());
  for (std::size_t i = 0; i < slots.size(); ++i) {
    const Slot& s = slots[i];
    FittedParam p;
    p.name = s.name;
    p.owner = s.owner;
    p.dim = s.info.dim;
    p.free = s.free;
    p.log_scale = s.log_scale;
    p.start = s.start;
    p.value = vals[i];
    p.lower = s.lower;
    p.upper = s.upper;
    res.params.push_back(p);
  }
  for (std::size_t j = 0; j < kk; ++j) {
    FittedParam& p = res.params[free[j]];
    const double sx = se_x(static_cast<Eigen::Index>(j));
    p.se = std::isfinite(sx) ? sx * ev.dsi_dx(j, x[j]) : kInf;
    p.at_bound = x[j] < 1e-3 || x[j] > 1.0 - 1e-3;
    if (p.at_bound) res.warnings.push_back("parameter " + p.name + " is at its " + (x[j] < 0.5 ? "lower" : "upper") + " bound " +
                                           format_quantity(x[j] < 0.5 ? p.lower : p.upper, p.dim));
    if (!std::isfinite(p.se)) res.warnings.push_back("parameter " + p.name + " is not identifiable from this record (no sensitivity)");
  }
  res.evaluations = ev.evaluations();
  res.model_description = ev.build(vals)->description();
  res.wall_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  return res;
}

namespace {

std::vector<std::string> split_list(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream ss(s);
  std::string item;
  while (std::getline(ss, item, ',')) {
    const auto b = item.find_first_not_of(' '), e = item.find_last_not_of(' ');
    if (b != std::string::npos) out.push_back(item.substr(b, e - b + 1));
  }
  return out;
}

// --set NAME=VALUE: a raw value for the law or an effect ("effect.param"), checked when the model
// is built (an unknown name or value is an InputError listing the valid ones).
void set_value(const std::string& arg, CalibrationOptions& o) {
  const auto eq = arg.find('=');
  if (eq == std::string::npos || eq == 0 || eq + 1 == arg.size()) {
    throw InputError("--set " + arg + ": write NAME=VALUE, e.g. --set dilation=reversible");
  }
  std::string name = arg.substr(0, eq);
  const std::string text = arg.substr(eq + 1);
  RawValue raw;
  raw.where = "--set " + arg;
  char* end = nullptr;
  const double num = std::strtod(text.c_str(), &end);
  if (text == "true" || text == "false") raw.value = text == "true";
  else if (end != text.c_str() && *end == '\0') raw.value = num;
  else raw.value = text;
  const auto dot = name.find('.');
  if (dot == std::string::npos) {
    o.law_values[name] = raw;
    return;
  }
  const std::string effect = name.substr(0, dot);
  if (std::find(o.effects.begin(), o.effects.end(), effect) == o.effects.end()) {
    throw InputError("--set " + arg + ": effect '" + effect + "' is not in --effects");
  }
  o.effect_values[effect][name.substr(dot + 1)] = raw;
}

// A laboratory case's stages, element settings and (same law) parameters as starting values.
void apply_case(const std::string& case_file, CalibrationOptions& opt, std::vector<std::string>& notes) {
  const LabTest test = read_lab_test(case_file);
  opt.stages = test.stages;
  bool per_stage = false;
  for (auto& s : opt.stages) {
    per_stage = per_stage || s.model != nullptr;
    s.model = nullptr;
  }
  if (per_stage) notes.push_back(case_file + ": per-stage parameters ([stage.params]) are not calibrated; one set is fitted to all stages");
  opt.element.max_step = test.step;
  opt.element.length = test.joint_length;
  opt.element.frame_stiffness = test.frame_stiffness;
  opt.element.frame_mass = test.frame_mass;
  if (test.law == opt.law) {
    opt.law_values = raw_values(test.joint_params, case_file, "joint.params");
  } else {
    notes.push_back(case_file + " is a " + test.law + " case; its parameters are not used as starting values for " + opt.law);
  }
  for (const auto& e : test.effects) {
    const auto* t = e.as_table();
    if (!t) continue;
    const auto* nm = t->get("name");
    if (!nm || !nm->is_string()) continue;
    const std::string name = nm->as_string()->get();
    if (std::find(opt.effects.begin(), opt.effects.end(), name) != opt.effects.end()) {
      opt.effect_values[name] = raw_values(*t, case_file, "joint.effects." + name, {"name"});
    }
  }
}

}  // namespace

void apply_inputs(const std::string& data_file, const MeasurementFile& data, const CalibrationInputs& in,
                  CalibrationOptions& opt, std::vector<std::string>& notes) {
  opt.law = in.law;
  opt.effects = split_list(in.effects);
  opt.free = in.free;
  for (const auto& f : in.fix) {
    const auto eq = f.find('=');
    if (eq == std::string::npos || eq == 0 || eq + 1 == f.size()) {
      throw InputError("--fix " + f + ": write NAME=VALUE, e.g. --fix friction=\"30 deg\"");
    }
    opt.fix_text[f.substr(0, eq)] = f.substr(eq + 1);
  }
  const std::string& case_file = in.case_file;
  if (data.rows.size() < 2) throw InputError(data_file + ": the record has fewer than two rows; nothing to calibrate");
  JointLawRegistry::instance().get(opt.law, "joint law", "--law");
  for (const auto& e : opt.effects) EffectRegistry::instance().get(e, "effect", "--effects");
  double length = 1.0;
  for (const auto& [k, v] : data.metadata)
    if (k == "joint_length_m") length = std::stod(v);
  opt.element.length = length;
  opt.element.max_step = 1e-5;  // the laboratory cases' element step, 0.01 mm
  if (!case_file.empty()) apply_case(case_file, opt, notes);
  for (const auto& a : in.set) set_value(a, opt);
}

nlohmann::json to_json(const CalibrationResult& r) {
  nlohmann::json j;
  j["law"] = r.law;
  j["effects"] = r.effects;
  j["model"] = r.model_description;
  j["status"] = r.status;
  j["converged"] = r.converged;
  j["iterations"] = r.iterations;
  j["evaluations"] = r.evaluations;
  auto nr = [](const std::array<double, 3>& a) {
    return nlohmann::json{{"shear_stress", a[0]}, {"normal_disp", a[1]}, {"combined", a[2]}};
  };
  j["nrmse"] = nr(r.nrmse);
  j["nrmse_fit_step"] = nr(r.nrmse_fit);
  j["rss"] = r.rss;
  j["n"] = r.n;
  j["k"] = r.k;
  j["bic"] = r.bic;
  j["params"] = nlohmann::json::object();
  j["parameters"] = nlohmann::json::array();
  for (const auto& p : r.params) {
    j["params"][p.name] = p.value;
    nlohmann::json e{{"name", p.name},        {"owner", p.owner},  {"unit", std::string(si_unit(p.dim))},
                     {"value", p.value},      {"start", p.start},  {"free", p.free},
                     {"display", format_quantity(p.value, p.dim)}};
    if (p.free) {
      e["se"] = std::isfinite(p.se) ? nlohmann::json(p.se) : nlohmann::json(nullptr);
      e["lower"] = p.lower;
      e["upper"] = p.upper;
      e["at_bound"] = p.at_bound;
      e["scale"] = p.log_scale ? "log" : "linear";
    }
    j["parameters"].push_back(e);
  }
  j["warnings"] = r.warnings;
  j["wall_ms"] = r.wall_ms;
  return j;
}

std::string format_table(const CalibrationResult& r) {
  std::ostringstream os;
  char buf[256];
  os << "parameter                         value          +- s.e.         unit    note\n";
  for (const auto& p : r.params) {
    // Angles in degrees, everything else in SI, so that value and error share one unit.
    const bool ang = p.dim == Dimension::angle;
    const double f = ang ? 1.0 / kDeg : 1.0;
    const std::string unit = ang ? "deg" : std::string(si_unit(p.dim));
    std::string se = p.free ? (std::isfinite(p.se) ? "" : "inf") : "fixed";
    if (p.free && std::isfinite(p.se)) {
      std::snprintf(buf, sizeof buf, "%.4g", p.se * f);
      se = buf;
    }
    std::string note = p.at_bound ? "AT BOUND" : "";
    if (p.free && !std::isfinite(p.se)) note += note.empty() ? "not identifiable" : ", not identifiable";
    std::snprintf(buf, sizeof buf, "  %-30s %-14.6g %-15s %-7s %s\n", p.name.c_str(), p.value * f, se.c_str(), unit.c_str(),
                  note.c_str());
    os << buf;
  }
  std::snprintf(buf, sizeof buf,
                "NRMSE: shear stress %.4f, normal displacement %.4f, combined %.4f (at the fitting step: %.4f)\n",
                r.nrmse[0], r.nrmse[1], r.nrmse[2], r.nrmse_fit[2]);
  os << buf;
  std::snprintf(buf, sizeof buf, "fit: %s after %d iterations, %ld model runs, %.0f ms; n = %zu residuals, k = %d, BIC %.1f\n",
                r.status.c_str(), r.iterations, r.evaluations, r.wall_ms, r.n, r.k, r.bic);
  os << buf;
  for (const auto& w : r.warnings) os << "warning: " << w << "\n";
  return os.str();
}

}  // namespace rockdem
