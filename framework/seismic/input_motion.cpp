#include "framework/seismic/input_motion.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <sstream>

#include <unsupported/Eigen/FFT>

#include "framework/core/error.hpp"
#include "framework/core/units.hpp"

namespace rockdem::seismic {

const char* motion_type_name(MotionType t) {
  switch (t) {
    case MotionType::outcrop: return "outcrop";
    case MotionType::incident: return "incident";
    case MotionType::within: return "within";
  }
  return "?";
}

std::string MotionScaling::describe() const {
  switch (kind) {
    case Kind::none: return "unscaled";
    case Kind::factor: return "scaled by " + std::to_string(value);
    case Kind::pga: return "scaled to PGA " + format_quantity(value, Dimension::acceleration);
    case Kind::pgv: return "scaled to PGV " + format_quantity(value, Dimension::velocity);
  }
  return "";
}

double InputMotion::sample(const std::vector<double>& x, double t) const {
  if (x.empty() || !(t >= 0.0)) return 0.0;
  const double s = t / dt;
  const auto i = static_cast<std::size_t>(s);
  if (i + 1 >= x.size()) return i + 1 == x.size() && s == static_cast<double>(i) ? x.back() : 0.0;
  const double w = s - static_cast<double>(i);
  return (1.0 - w) * x[i] + w * x[i + 1];
}

double InputMotion::displacement(double t) const {
  if (disp.empty() || !(t >= 0.0)) return 0.0;
  return t >= duration() ? disp.back() : sample(disp, t);
}

double InputMotion::pga() const { return peak_abs(acc); }
double InputMotion::pgv() const { return peak_abs(vel); }
double InputMotion::pgd() const { return peak_abs(disp); }

double InputMotion::factor_for(const MotionScaling& s) const {
  auto to = [&](double peak, const char* what) {
    if (!(peak > 0.0)) throw InputError("motion '" + name + "' has a zero " + what + "; it cannot be scaled to a peak");
    return s.value / peak;
  };
  switch (s.kind) {
    case MotionScaling::Kind::none: return 1.0;
    case MotionScaling::Kind::factor: return s.value;
    case MotionScaling::Kind::pga: return to(pga(), "acceleration");
    case MotionScaling::Kind::pgv: return to(pgv(), "velocity");
  }
  return 1.0;
}

InputMotion make_input_motion(const GroundMotion& g, const DisplacementProcessing& p, const MotionScaling& s) {
  ProcessedMotion pm = process_to_displacement(g, p);
  InputMotion m;
  m.dt = pm.dt;
  m.acc = std::move(pm.acc);
  m.vel = std::move(pm.vel);
  m.disp = std::move(pm.disp);
  m.f_high = p.f_high;
  // A motion must end at rest: a velocity left at the end of the record would stop abruptly when
  // the input does (a step that sends a spurious wave into the model) or, at a rigid base, leave
  // the model drifting. The usual processing (baseline, taper, filter) leaves some; a constant
  // removed from the acceleration takes the final velocity to zero exactly (the displacement
  // follows consistently).
  const double duration = m.dt * static_cast<double>(m.acc.size() - 1);
  const double a0 = m.vel.back() / duration;
  for (std::size_t i = 0; i < m.acc.size(); ++i) {
    const double t = m.dt * static_cast<double>(i);
    m.acc[i] -= a0;
    m.vel[i] -= a0 * t;
    m.disp[i] -= 0.5 * a0 * t * t;
  }
  const double f = m.factor_for(s);
  if (!std::isfinite(f) || !(f > 0.0)) throw InputError("motion scaling gives a factor of " + std::to_string(f));
  for (auto* x : {&m.acc, &m.vel, &m.disp})
    for (double& v : *x) v *= f;
  m.scale = f;
  m.source = g.source + " (" + g.column_name + ")";
  std::ostringstream end;
  end << "; final velocity " << a0 * duration << " m/s taken out (a constant " << a0 << " m/s2 removed from the acceleration)";
  m.processing = p.describe() + end.str() + "; " + s.describe() + " (factor " + std::to_string(f) + ")";
  return m;
}

double mesh_frequency_limit(double cs, double zone_size, double zones_per_wavelength) {
  return cs / (zones_per_wavelength * zone_size);
}

double power_frequency(std::span<const double> x, double dt, double fraction) {
  if (x.size() < 4) return 0.5 / dt;
  Eigen::FFT<double> fft;
  std::vector<double> in(x.begin(), x.end());
  std::vector<std::complex<double>> spec;
  fft.fwd(spec, in);
  const std::size_t half = x.size() / 2;
  double total = 0.0;
  for (std::size_t k = 1; k <= half; ++k) total += std::norm(spec[k]);
  if (!(total > 0.0)) return 0.0;
  double sum = 0.0;
  for (std::size_t k = 1; k <= half; ++k) {
    sum += std::norm(spec[k]);
    if (sum >= fraction * total) return static_cast<double>(k) / (dt * static_cast<double>(x.size()));
  }
  return 0.5 / dt;
}

}  // namespace rockdem::seismic
