#include "framework/seismic/sdof.hpp"

#include <cmath>
#include <numbers>
#include <sstream>
#include <string>

#include "framework/core/error.hpp"
#include "framework/core/units.hpp"

namespace rockdem::seismic {
namespace {}  // namespace

SdofResponse sdof_response(std::span<const double> ag, double dt, const SdofOscillator& osc, double u0, double v0) {
  if (!(osc.period > 0.0) || !std::isfinite(osc.period)) {
    throw InputError("SDOF period " + format_quantity(osc.period, Dimension::time) +
                     " is invalid; valid: a positive period");
  }
  if (!(osc.damping >= 0.0 && osc.damping < 1.0)) {
    throw InputError("SDOF damping ratio " + format_quantity(osc.damping, Dimension::dimensionless) +
                     " is invalid; valid: 0 <= damping < 1 (under-damped)");
  }
  if (!(dt > 0.0) || !std::isfinite(dt))
    throw InputError("SDOF time step " + format_quantity(dt, Dimension::time) + " must be positive");
  // Chopra (5th ed.), Table 5.2.1, with m = 1, k = wn^2 and load p = -ag:
  //   u_{i+1} = A u_i + B v_i + C p_i + D p_{i+1},  v_{i+1} = A' u_i + B' v_i + C' p_i + D' p_{i+1}.
  const double z = osc.damping;
  const double wn = 2.0 * std::numbers::pi / osc.period;
  const double r = std::sqrt(1.0 - z * z);
  const double wd = wn * r;
  const double k = wn * wn;
  const double e = std::exp(-z * wn * dt);
  const double s = std::sin(wd * dt), c = std::cos(wd * dt);
  const double A = e * (z / r * s + c);
  const double B = e * s / wd;
  const double C =
      (2.0 * z / (wn * dt) + e * (((1.0 - 2.0 * z * z) / (wd * dt) - z / r) * s - (1.0 + 2.0 * z / (wn * dt)) * c)) / k;
  const double D =
      (1.0 - 2.0 * z / (wn * dt) + e * ((2.0 * z * z - 1.0) / (wd * dt) * s + 2.0 * z / (wn * dt) * c)) / k;
  const double Ap = -e * wn / r * s;
  const double Bp = e * (c - z / r * s);
  const double Cp = (-1.0 / dt + e * ((wn / r + z / (dt * r)) * s + c / dt)) / k;
  const double Dp = (1.0 - e * (z / r * s + c)) / (k * dt);
  SdofResponse out;
  out.u.resize(ag.size());
  out.v.resize(ag.size());
  if (ag.empty()) return out;
  out.u[0] = u0;
  out.v[0] = v0;
  for (std::size_t i = 0; i + 1 < ag.size(); ++i) {
    const double p0 = -ag[i], p1 = -ag[i + 1];
    out.u[i + 1] = A * out.u[i] + B * out.v[i] + C * p0 + D * p1;
    out.v[i + 1] = Ap * out.u[i] + Bp * out.v[i] + Cp * p0 + Dp * p1;
  }
  return out;
}

double sdof_peak_displacement(std::span<const double> ag, double dt, const SdofOscillator& osc) {
  const auto r = sdof_response(ag, dt, osc);
  double m = 0.0;
  for (double x : r.u) m = std::max(m, std::abs(x));
  return m;
}

}  // namespace rockdem::seismic
