#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "framework/analysis/calibration.hpp"
#include "framework/analysis/calibration_fit.hpp"
#include "framework/core/error.hpp"

namespace rockdem {
namespace {

using calibration_detail::kDeg;
using calibration_detail::log_dimension;
using calibration_detail::physical_range;
using calibration_detail::Slot;

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

// The record's estimate of a law parameter, if it gives one (slots: the values so far).
std::optional<double> estimate_for(const Slot& s, const std::vector<Slot>& slots, const DataEstimates& est,
                                   const MeasurementFile& data) {
  const bool has_initial_friction = std::any_of(slots.begin(), slots.end(), [](const Slot& o) { return o.name == "initial_friction"; });
  auto slot_value = [&](const std::string& n, double fallback) {
    for (const auto& o : slots)
      if (o.name == n && std::isfinite(o.value)) return o.value;
    return fallback;
  };
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
}

// The registry's bounds tightened to physical ones, and the scale the fit moves on.
void set_bounds(Slot& s) {
  const auto [plo, phi] = physical_range(s.info.dim);
  s.lower = std::max(s.info.min, plo);
  s.upper = std::min(s.info.max, phi);
  if (s.info.min_open) s.lower = std::max(s.lower, s.info.min + 1e-9 * std::max(1.0, std::abs(s.info.min)));
  if (s.info.max_open) s.upper = std::min(s.upper, s.info.max - 1e-9 * std::max(1.0, std::abs(s.info.max)));
  s.log_scale = log_dimension(s.info.dim) && s.lower > 0.0;
}

}  // namespace

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

namespace calibration_detail {

void set_bounds_and_starts(std::vector<Slot>& slots, const MeasurementFile& data, const Segmentation& seg,
                           const CalibrationOptions& options, const std::map<std::string, double>& fix,
                           std::vector<std::string>& warnings) {
  const DataEstimates est = estimate_from_data(data, seg);
  for (auto& s : slots) {
    set_bounds(s);
    auto ws = options.start.find(s.name);
    if (ws != options.start.end() && !fix.count(s.name)) {
      s.value = ws->second;
    } else if (!s.given) {
      if (auto v = estimate_for(s, slots, est, data); v && (s.free || !std::isfinite(s.value))) s.value = *v;
    }
    if (!std::isfinite(s.value) && s.free) s.value = s.log_scale ? std::sqrt(s.lower * s.upper) : 0.5 * (s.lower + s.upper);
    if (std::isnan(s.value)) {
      throw InputError("calibrate: parameter '" + s.name + "' has no default and cannot be estimated from the data; "
                       "give it with --fix " + s.name + "=VALUE or a --case");
    }
    if (s.free) s.value = std::clamp(s.value, s.lower, s.upper);
    s.start = s.value;
  }
  if (est.ks <= 0.0) warnings.push_back("no initial elastic slope found in the record; ks starts from a default");
}

}  // namespace calibration_detail
}  // namespace rockdem
