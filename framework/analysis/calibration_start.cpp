#include <algorithm>
#include <cmath>

#include "framework/analysis/calibration.hpp"
#include "framework/analysis/calibration_fit.hpp"

namespace rockdem {
namespace {

using calibration_detail::kDeg;

double median_of(std::vector<double> v) {
  if (v.empty()) return 0.0;
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
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

}  // namespace rockdem
