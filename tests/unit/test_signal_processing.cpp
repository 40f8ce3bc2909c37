// Signal processing of accelerograms (framework/seismic/signal_processing.hpp): the zero-phase
// Butterworth filter passes and blocks sinusoids with the designed gain and no delay, baselines
// remove polynomial drifts, the trapezoid rule integrates known functions, and the whole
// acceleration -> displacement chain recovers the displacement of a known motion.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "framework/core/error.hpp"
#include "framework/seismic/signal_processing.hpp"

using namespace rockdem;
using namespace rockdem::seismic;

namespace {

constexpr double kPi = std::numbers::pi;

std::vector<double> sine(double f, double dt, std::size_t n, double amplitude = 1.0) {
  std::vector<double> x(n);
  for (std::size_t i = 0; i < n; ++i) x[i] = amplitude * std::sin(2.0 * kPi * f * dt * static_cast<double>(i));
  return x;
}

// Gain of a zero-phase filter at f, from a long sinusoid: least-squares amplitudes of the sine and
// cosine parts over the middle half (away from the ends' transients). Returns {gain, cosine part}.
std::pair<double, double> zero_phase_gain(double f, double dt, const std::vector<Biquad>& s) {
  const std::size_t n = 40000;
  auto x = sine(f, dt, n);
  filter_zero_phase(x, s);
  double ss = 0, sc = 0, cc = 0, xs = 0, xc = 0;
  for (std::size_t i = n / 4; i < 3 * n / 4; ++i) {
    const double ph = 2.0 * kPi * f * dt * static_cast<double>(i);
    const double si = std::sin(ph), co = std::cos(ph);
    ss += si * si;
    sc += si * co;
    cc += co * co;
    xs += x[i] * si;
    xc += x[i] * co;
  }
  const double det = ss * cc - sc * sc;
  return {(xs * cc - xc * sc) / det, (xc * ss - xs * sc) / det};
}

}  // namespace

TEST(SignalProcessing, ButterworthZeroPhasePassesAndBlocks) {
  const double dt = 0.01;  // Nyquist 50 Hz
  const auto band = butterworth_bandpass(dt, 0.2, 2.0, 2);
  ASSERT_EQ(band.size(), 2u);
  // In the pass band the sinusoid comes through whole and in phase (no cosine part = no delay).
  auto [g, q] = zero_phase_gain(0.6, dt, band);
  EXPECT_NEAR(g, 1.0, 0.03);
  EXPECT_NEAR(q, 0.0, 1e-6);
  // Far outside, it is blocked: order 2 each way falls as f^4 per decade past a corner.
  EXPECT_LT(std::abs(zero_phase_gain(20.0, dt, band).first), 2e-3);
  EXPECT_LT(std::abs(zero_phase_gain(0.02, dt, band).first), 2e-3);
  // At a corner the one-way Butterworth gain is 1/sqrt(2), so forward-backward gives 1/2: the
  // prewarped bilinear transform puts the corner exactly where asked, for any order.
  for (int order : {1, 2, 3, 4}) {
    EXPECT_NEAR(zero_phase_gain(5.0, dt, butterworth_bandpass(dt, 5.0, 0.0, order)).first, 0.5, 2e-3) << order;
    EXPECT_NEAR(zero_phase_gain(5.0, dt, butterworth_bandpass(dt, 0.0, 5.0, order)).first, 0.5, 2e-3) << order;
  }
}

TEST(SignalProcessing, ButterworthRejectsBadCorners) {
  EXPECT_THROW(butterworth_bandpass(0.02, 0.5, 0.2, 2), InputError);   // corners swapped
  EXPECT_THROW(butterworth_bandpass(0.02, 0.1, 25.0, 2), InputError);  // at Nyquist
  EXPECT_THROW(butterworth_bandpass(0.02, 0.1, 2.0, 0), InputError);
  EXPECT_THROW(butterworth_bandpass(0.02, -0.1, 2.0, 2), InputError);
  EXPECT_TRUE(butterworth_bandpass(0.02, 0.0, 0.0, 2).empty());
}

TEST(SignalProcessing, BaselineRemovesPolynomialDrift) {
  const double dt = 0.02;
  const std::size_t n = 2000;
  // 20 whole cycles of a cosine: orthogonal to 1 and t (a sine is not: it projects on t).
  std::vector<double> wave(n);
  for (std::size_t i = 0; i < n; ++i) wave[i] = std::cos(2.0 * kPi * 0.5 * dt * static_cast<double>(i));
  std::vector<double> x(n);
  for (std::size_t i = 0; i < n; ++i) x[i] = wave[i] + 0.3 - 0.05 * dt * static_cast<double>(i);
  remove_polynomial_baseline(x, dt, 1);
  double err = 0;
  for (std::size_t i = 0; i < n; ++i) err = std::max(err, std::abs(x[i] - wave[i]));
  EXPECT_LT(err, 3e-3);  // the drift reaches 1.9; left: the sampled wave's tiny projection
  // An exact line is removed to round-off.
  std::vector<double> line(n);
  for (std::size_t i = 0; i < n; ++i) line[i] = 1.7 + 0.4 * dt * static_cast<double>(i);
  remove_polynomial_baseline(line, dt, 1);
  for (double v : line) EXPECT_NEAR(v, 0.0, 1e-12);
  // Powers 2..3 only (a displacement that starts at rest): an exact cubic drift is removed to
  // round-off, with its derivatives, and the fit leaves the start at rest.
  std::vector<double> d(n), drift(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double t = dt * static_cast<double>(i);
    drift[i] = 2e-3 * t * t - 1e-4 * t * t * t;
  }
  d = drift;
  const auto fit = remove_polynomial_baseline(d, dt, 3, 2);
  EXPECT_NEAR(fit.value(0.0), 0.0, 1e-15);
  EXPECT_NEAR(fit.rate(0.0), 0.0, 1e-15);
  EXPECT_NEAR(fit.rate(10.0), 2 * 2e-3 * 10.0 - 3 * 1e-4 * 100.0, 1e-12);
  EXPECT_NEAR(fit.rate2(10.0), 2 * 2e-3 - 6 * 1e-4 * 10.0, 1e-12);
  for (double v : d) EXPECT_NEAR(v, 0.0, 1e-12);
  // With a wave on top, the drift (3.2 m at the end) goes and the wave (1 mm) stays, less its
  // own small projection on t^2 and t^3.
  for (std::size_t i = 0; i < n; ++i) d[i] = 1e-3 * wave[i] + drift[i];
  remove_polynomial_baseline(d, dt, 3, 2);
  for (std::size_t i = 0; i < n; ++i) EXPECT_NEAR(d[i], 1e-3 * wave[i], 2e-4);
  EXPECT_THROW(remove_polynomial_baseline(d, dt, 1, 2), InputError);
}

TEST(SignalProcessing, TrapezoidIntegratesKnownFunctions) {
  const double dt = 1e-3;
  const std::size_t n = 5001;
  // Exact for a linear integrand: int (3 + 2t) = 3t + t^2.
  std::vector<double> lin(n);
  for (std::size_t i = 0; i < n; ++i) lin[i] = 3.0 + 2.0 * dt * static_cast<double>(i);
  const auto y = integrate_trapezoid(lin, dt, 1.0);
  for (std::size_t i = 0; i < n; ++i) {
    const double t = dt * static_cast<double>(i);
    EXPECT_NEAR(y[i], 1.0 + 3.0 * t + t * t, 1e-11);
  }
  // Second order for a smooth one: int cos(w t) = sin(w t) / w, error <= T w^2 dt^2 / 12.
  const double w = 2.0 * kPi * 0.7;
  std::vector<double> c(n);
  for (std::size_t i = 0; i < n; ++i) c[i] = std::cos(w * dt * static_cast<double>(i));
  const auto s = integrate_trapezoid(c, dt);
  for (std::size_t i = 0; i < n; i += 50) {
    const double t = dt * static_cast<double>(i);
    EXPECT_NEAR(s[i], std::sin(w * t) / w, 5.0 * w * w * dt * dt / 12.0);
  }
}

TEST(SignalProcessing, DominantFrequencyTaperAndScale) {
  const double dt = 0.02;
  const std::size_t n = 3000;  // 60 s: bins every 1/60 Hz
  auto x = sine(0.5, dt, n, 1.0);
  const auto y = sine(3.0, dt, n, 0.4);
  for (std::size_t i = 0; i < n; ++i) x[i] += y[i] + 0.8;  // the mean (0 Hz) is not a frequency
  EXPECT_NEAR(dominant_frequency(x, dt), 0.5, 1.0 / 60.0);
  const auto z = sine(3.0, dt, n, 2.0);
  std::vector<double> mix(n);
  for (std::size_t i = 0; i < n; ++i) mix[i] = z[i] + 0.5 * x[i];
  EXPECT_NEAR(dominant_frequency(mix, dt), 3.0, 1.0 / 60.0);

  std::vector<double> ones(101, 1.0);
  cosine_taper(ones, 0.1, 2.0);  // 20 samples each end
  EXPECT_DOUBLE_EQ(ones.front(), 0.0);
  EXPECT_DOUBLE_EQ(ones.back(), 0.0);
  EXPECT_NEAR(ones[10], 0.5, 1e-12);
  EXPECT_NEAR(ones[90], 0.5, 1e-12);
  EXPECT_DOUBLE_EQ(ones[50], 1.0);
  EXPECT_DOUBLE_EQ(ones[20], 1.0);
  EXPECT_THROW(cosine_taper(ones, 0.1, 6.0), InputError);

  std::vector<double> v{0.1, -0.4, 0.2};
  EXPECT_DOUBLE_EQ(scale_to_peak(v, 2.0), 5.0);
  EXPECT_DOUBLE_EQ(v[1], -2.0);
  std::vector<double> zero(5, 0.0);
  EXPECT_THROW(scale_to_peak(zero, 1.0), InputError);
}

TEST(SignalProcessing, ChainRecoversTheDisplacementOfAKnownMotion) {
  // Ground displacement u = A sin(w t) e(t) under a slow envelope; its acceleration, sampled,
  // goes through window, baseline, taper, pads, band-pass, double integration and scaling.
  const double dt = 0.02, f = 0.5, w = 2.0 * kPi * f, A = 0.03;
  const std::size_t n = 4001;  // 80 s
  GroundMotion g;
  g.source = "synthetic";
  g.dt = dt;
  g.acc.resize(n);
  std::vector<double> u(n);
  const double T = dt * static_cast<double>(n - 1);
  for (std::size_t i = 0; i < n; ++i) {
    const double t = dt * static_cast<double>(i);
    const double e = std::pow(std::sin(kPi * t / T), 2);  // zero value and slope at both ends
    const double de = kPi / T * std::sin(2.0 * kPi * t / T), dde = 2.0 * kPi * kPi / (T * T) * std::cos(2.0 * kPi * t / T);
    u[i] = A * std::sin(w * t) * e;
    g.acc[i] = A * (-w * w * std::sin(w * t) * e + 2.0 * w * std::cos(w * t) * de + std::sin(w * t) * dde);
  }
  DisplacementProcessing p;
  p.acc_baseline_degree = 1;
  p.taper = 2.0;
  p.pad = 20.0;
  p.f_low = 0.05;
  p.f_high = 5.0;
  p.order = 2;
  const auto m = process_to_displacement(g, p);
  ASSERT_EQ(m.disp.size(), n + 2000);
  const std::size_t off = 1000;  // 20 s of pad
  double err = 0;
  for (std::size_t i = 0; i < n; ++i) err = std::max(err, std::abs(m.disp[off + i] - u[i]));
  EXPECT_LT(err, 0.02 * A);
  EXPECT_LT(std::abs(m.disp.back()), 0.01 * A);
  EXPECT_NEAR(dominant_frequency(m.disp, dt), f, 1.0 / (dt * static_cast<double>(m.disp.size())));
  // Scaling applies to all three histories alike.
  p.peak_displacement = 0.0254;
  const auto s = process_to_displacement(g, p);
  EXPECT_NEAR(peak_abs(s.disp), 0.0254, 1e-15);
  EXPECT_NEAR(s.vel[2000] / m.vel[2000], s.scale, 1e-9);
  // A window outside the record is refused.
  p.start = 70.0;
  p.end = 90.0;
  EXPECT_THROW(process_to_displacement(g, p), InputError);
}
