#include "framework/seismic/signal_processing.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>
#include <sstream>
#include <unsupported/Eigen/FFT>

#include "framework/core/error.hpp"
#include "framework/core/units.hpp"

namespace rockdem::seismic {
namespace {

void check_dt(double dt, const char* who) {
  if (!(dt > 0.0) || !std::isfinite(dt))
    throw InputError(std::string(who) + ": time step " + format_quantity(dt, Dimension::time) + " must be positive");
}

// A length in samples. The ratio is checked in floating point before it is rounded: with a tiny
// dt, lround(2 s / 1e-300 s) overflows, and the garbage it returns passed the later length
// checks and the taper wrote past the end of its vector. 1e9 samples (8 GB of doubles) is far
// beyond any record and keeps 2 * m and nb + n + na free of overflow.
std::size_t samples(double seconds, double dt, const char* who) {
  constexpr double kMaxSamples = 1e9;
  const double r = seconds / dt;
  if (!(r >= 0.0 && r <= kMaxSamples)) {
    throw InputError(std::string(who) + " of " + format_quantity(seconds, Dimension::time) + " at a time step of " +
                     format_quantity(dt, Dimension::time) + " is " + format_quantity(r, Dimension::dimensionless) +
                     " samples; valid: at most 1e9 samples");
  }
  return static_cast<std::size_t>(std::lround(r));
}

}  // namespace

double PolynomialFit::eval(double tau, int derivative) const {
  const double s = tau / duration;
  double v = 0.0;
  for (std::size_t k = 0; k < coeff.size(); ++k) {
    const int p = lowest + static_cast<int>(k);
    if (p < derivative) continue;
    double f = 1.0;
    for (int j = 0; j < derivative; ++j) f *= static_cast<double>(p - j);
    v += coeff[k] * f * std::pow(s, p - derivative);
  }
  return v / std::pow(duration, derivative);
}

PolynomialFit remove_polynomial_baseline(std::vector<double>& x, double dt, int degree, int lowest) {
  check_dt(dt, "baseline");
  if (lowest < 0 || degree < lowest || degree > 10) {
    throw InputError("baseline polynomial: powers " + std::to_string(lowest) + ".." + std::to_string(degree) +
                     " are invalid; valid: 0 <= lowest power <= degree <= 10");
  }
  const auto n = static_cast<Eigen::Index>(x.size());
  const int m = degree - lowest + 1;
  if (n < m + 1)
    throw InputError("baseline polynomial of degree " + std::to_string(degree) + " needs more than " +
                     std::to_string(m) + " samples; the signal has " + std::to_string(n));
  // Powers of tau / T (in [0, 1]) keep the normal matrix well conditioned for any record length.
  const double T = dt * static_cast<double>(n - 1);
  Eigen::MatrixXd A(n, m);
  for (Eigen::Index i = 0; i < n; ++i) {
    const double s = dt * static_cast<double>(i) / T;
    for (int k = 0; k < m; ++k) A(i, k) = std::pow(s, lowest + k);
  }
  const Eigen::Map<const Eigen::VectorXd> b(x.data(), n);
  const Eigen::VectorXd c = A.colPivHouseholderQr().solve(b);
  const Eigen::VectorXd fit = A * c;
  for (Eigen::Index i = 0; i < n; ++i) x[static_cast<std::size_t>(i)] -= fit(i);
  return PolynomialFit{std::vector<double>(c.data(), c.data() + m), lowest, T};
}

void cosine_taper(std::vector<double>& x, double dt, double length) {
  check_dt(dt, "taper");
  if (length < 0.0)
    throw InputError("taper length " + format_quantity(length, Dimension::time) + " must not be negative");
  const std::size_t m = samples(length, dt, "--taper");
  if (m > x.size() / 2) {
    throw InputError(
        "taper of " + format_quantity(length, Dimension::time) + " at both ends is longer than the signal (" +
        format_quantity(dt * static_cast<double>(x.size()), Dimension::time) + "); valid: at most half its length");
  }
  for (std::size_t i = 0; i < m; ++i) {
    const double w = 0.5 * (1.0 - std::cos(std::numbers::pi * static_cast<double>(i) / static_cast<double>(m)));
    x[i] *= w;
    x[x.size() - 1 - i] *= w;
  }
}

std::vector<double> zero_pad(std::span<const double> x, double dt, double before, double after) {
  check_dt(dt, "zero padding");
  if (before < 0.0 || after < 0.0) throw InputError("zero pads must not be negative");
  const std::size_t nb = samples(before, dt, "--pad"), na = samples(after, dt, "--pad");
  std::vector<double> out(nb + x.size() + na, 0.0);
  std::copy(x.begin(), x.end(), out.begin() + static_cast<std::ptrdiff_t>(nb));
  return out;
}

std::vector<Biquad> butterworth_bandpass(double dt, double f_low, double f_high, int order) {
  check_dt(dt, "Butterworth filter");
  const double nyquist = 0.5 / dt;
  if (order < 1 || order > 8) throw InputError("filter order " + std::to_string(order) + " is invalid; valid: 1..8");
  if (f_low < 0.0 || f_low >= nyquist || f_high < 0.0 || f_high >= nyquist) {
    throw InputError("filter corners " + format_quantity(f_low, Dimension::frequency) + " and " +
                     format_quantity(f_high, Dimension::frequency) + ": valid corners are in [0, " +
                     format_quantity(nyquist, Dimension::frequency) + ") (the Nyquist frequency), 0 = off");
  }
  if (f_low > 0.0 && f_high > 0.0 && f_low >= f_high) {
    throw InputError("filter corners: the high-pass corner " + format_quantity(f_low, Dimension::frequency) +
                     " must be below the low-pass corner " + format_quantity(f_high, Dimension::frequency));
  }
  std::vector<Biquad> out;
  // Analog Butterworth prototype: conjugate pole pairs s^2 + s/Q_k + 1 with
  // Q_k = 1 / (2 sin((2k+1) pi / (2n))), plus s + 1 for odd n. Bilinear transform
  // s = (1/K)(1 - z^-1)/(1 + z^-1), K = tan(pi f_c dt), so the digital corner is exactly f_c
  // (Oppenheim & Schafer, Discrete-Time Signal Processing, 3rd ed., section 7.2).
  auto add = [&](double fc, bool high) {
    const double K = std::tan(std::numbers::pi * fc * dt);
    for (int k = 0; k < order / 2; ++k) {
      const double q = 1.0 / (2.0 * std::sin((2.0 * k + 1.0) * std::numbers::pi / (2.0 * order)));
      const double a0 = 1.0 + K / q + K * K;
      const double g = high ? 1.0 / a0 : K * K / a0;
      out.push_back({g, high ? -2.0 * g : 2.0 * g, g, (2.0 * K * K - 2.0) / a0, (1.0 - K / q + K * K) / a0});
    }
    if (order % 2 == 1) {
      const double a0 = 1.0 + K;
      const double g = high ? 1.0 / a0 : K / a0;
      out.push_back({g, high ? -g : g, 0.0, (K - 1.0) / a0, 0.0});
    }
  };
  if (f_low > 0.0) add(f_low, true);
  if (f_high > 0.0) add(f_high, false);
  return out;
}

void filter_forward(std::vector<double>& x, const std::vector<Biquad>& sections) {
  for (const auto& s : sections) {
    double z1 = 0.0, z2 = 0.0;
    for (double& v : x) {
      const double y = s.b0 * v + z1;
      z1 = s.b1 * v - s.a1 * y + z2;
      z2 = s.b2 * v - s.a2 * y;
      v = y;
    }
  }
}

void filter_zero_phase(std::vector<double>& x, const std::vector<Biquad>& sections) {
  filter_forward(x, sections);
  std::reverse(x.begin(), x.end());
  filter_forward(x, sections);
  std::reverse(x.begin(), x.end());
}

std::vector<double> integrate_trapezoid(std::span<const double> x, double dt, double initial) {
  check_dt(dt, "integration");
  std::vector<double> y(x.size());
  if (x.empty()) return y;
  y[0] = initial;
  for (std::size_t i = 1; i < x.size(); ++i) y[i] = y[i - 1] + 0.5 * dt * (x[i - 1] + x[i]);
  return y;
}

double dominant_frequency(std::span<const double> x, double dt) {
  check_dt(dt, "dominant frequency");
  if (x.size() < 4)
    throw InputError("dominant frequency: the signal has " + std::to_string(x.size()) +
                     " samples; at least 4 are needed");
  Eigen::FFT<double> fft;
  std::vector<double> in(x.begin(), x.end());
  std::vector<std::complex<double>> spec;
  fft.fwd(spec, in);
  std::size_t best = 1;
  for (std::size_t k = 2; k <= x.size() / 2; ++k)
    if (std::abs(spec[k]) > std::abs(spec[best])) best = k;
  return static_cast<double>(best) / (dt * static_cast<double>(x.size()));
}

double peak_abs(std::span<const double> x) {
  double m = 0.0;
  for (double v : x) m = std::max(m, std::abs(v));
  return m;
}

double scale_to_peak(std::vector<double>& x, double target) {
  const double p = peak_abs(x);
  if (!(p > 0.0)) throw InputError("cannot scale a signal that is zero everywhere to a peak");
  const double f = target / p;
  for (double& v : x) v *= f;
  return f;
}

std::string DisplacementProcessing::describe() const {
  std::ostringstream os;
  os << "window " << (start < 0 ? std::string("first sample") : format_quantity(start, Dimension::time)) << " to "
     << (end < 0 ? std::string("last sample") : format_quantity(end, Dimension::time)) << "; acceleration baseline "
     << (acc_baseline_degree < 0 ? std::string("none") : "polynomial degree " + std::to_string(acc_baseline_degree))
     << "; cosine taper " << format_quantity(taper, Dimension::time) << "; zero pads "
     << format_quantity(pad, Dimension::time) << "; zero-phase Butterworth order " << order << " high-pass "
     << (f_low > 0 ? format_quantity(f_low, Dimension::frequency) : std::string("off")) << " low-pass "
     << (f_high > 0 ? format_quantity(f_high, Dimension::frequency) : std::string("off"))
     << "; trapezoid integration; displacement baseline "
     << (disp_baseline_degree > 0 ? "powers 2.." + std::to_string(disp_baseline_degree) : std::string("none"))
     << "; peak "
     << (peak_displacement > 0 ? format_quantity(peak_displacement * 1e3, Dimension::dimensionless) + " mm"
                               : std::string("unscaled"));
  return os.str();
}

void DisplacementProcessing::validate(double dt) const {
  if (start >= 0 && end >= 0 && end <= start) {
    throw InputError("window: end " + format_quantity(end, Dimension::time) + " must be after start " +
                     format_quantity(start, Dimension::time));
  }
  if (acc_baseline_degree < -1 || acc_baseline_degree > 10) {
    throw InputError("acceleration baseline degree " + std::to_string(acc_baseline_degree) +
                     " is invalid; valid: -1 (none) to 10");
  }
  if (disp_baseline_degree != 0 && (disp_baseline_degree < 2 || disp_baseline_degree > 10)) {
    throw InputError("displacement baseline degree " + std::to_string(disp_baseline_degree) +
                     " is invalid; valid: 0 (none) or 2..10 (powers 2..degree, so the motion starts at rest)");
  }
  if (taper < 0.0) throw InputError("taper " + format_quantity(taper, Dimension::time) + " must not be negative");
  if (pad < 0.0) throw InputError("pad " + format_quantity(pad, Dimension::time) + " must not be negative");
  if (peak_displacement < 0.0) throw InputError("peak displacement must not be negative (0: no scaling)");
  butterworth_bandpass(dt, f_low, f_high, order);  // checks corners and order
}

ProcessedMotion process_to_displacement(const GroundMotion& g, const DisplacementProcessing& p) {
  p.validate(g.dt);
  const double t_last = g.t0 + g.duration();
  const double tol = 1e-6 * g.dt;
  if ((p.start >= 0 && (p.start < g.t0 - tol || p.start > t_last + tol)) ||
      (p.end >= 0 && (p.end < g.t0 - tol || p.end > t_last + tol))) {
    throw InputError("window " + format_quantity(p.start, Dimension::time) + " to " +
                     format_quantity(p.end, Dimension::time) + " is outside the record " + g.source + " (" +
                     format_quantity(g.t0, Dimension::time) + " to " + format_quantity(t_last, Dimension::time) + ")");
  }
  const std::size_t i0 = p.start < 0 ? 0 : static_cast<std::size_t>(std::ceil((p.start - g.t0) / g.dt - 1e-6));
  const std::size_t i1 =
      p.end < 0 ? g.acc.size() - 1 : static_cast<std::size_t>(std::floor((p.end - g.t0) / g.dt + 1e-6));
  if (i1 < i0 + 3)
    throw InputError("window " + format_quantity(p.start, Dimension::time) + " to " +
                     format_quantity(p.end, Dimension::time) + " holds fewer than 4 samples");
  std::vector<double> a(g.acc.begin() + static_cast<std::ptrdiff_t>(i0),
                        g.acc.begin() + static_cast<std::ptrdiff_t>(i1 + 1));
  if (p.acc_baseline_degree >= 0) remove_polynomial_baseline(a, g.dt, p.acc_baseline_degree);
  cosine_taper(a, g.dt, p.taper);
  a = zero_pad(a, g.dt, p.pad, p.pad);
  filter_zero_phase(a, butterworth_bandpass(g.dt, p.f_low, p.f_high, p.order));

  ProcessedMotion out;
  out.dt = g.dt;
  out.record_start = g.t0 + g.dt * static_cast<double>(i0);
  out.vel = integrate_trapezoid(a, g.dt);
  out.disp = integrate_trapezoid(out.vel, g.dt);
  if (p.disp_baseline_degree >= 2) {
    // The removed polynomial has zero value and slope at t = 0; subtracting its derivatives from
    // velocity and acceleration keeps the three histories consistent.
    const auto fit = remove_polynomial_baseline(out.disp, g.dt, p.disp_baseline_degree, 2);
    for (std::size_t i = 0; i < a.size(); ++i) {
      const double tau = g.dt * static_cast<double>(i);
      out.vel[i] -= fit.rate(tau);
      a[i] -= fit.rate2(tau);
    }
  }
  out.acc = std::move(a);
  if (p.peak_displacement > 0.0) {
    out.scale = scale_to_peak(out.disp, p.peak_displacement);
    for (double& v : out.vel) v *= out.scale;
    for (double& v : out.acc) v *= out.scale;
  }
  out.time.resize(out.disp.size());
  for (std::size_t i = 0; i < out.time.size(); ++i) out.time[i] = g.dt * static_cast<double>(i);
  return out;
}

}  // namespace rockdem::seismic
