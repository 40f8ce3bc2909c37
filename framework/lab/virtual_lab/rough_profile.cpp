#include "framework/lab/virtual_lab/rough_profile.hpp"

#include <cmath>
#include <complex>
#include <numbers>
#include <string>

#include "framework/core/error.hpp"

namespace rockdem::vlab {

SeededRandom::SeededRandom(std::uint64_t seed) : engine_(seed) {}

double SeededRandom::uniform() {
  return static_cast<double>(engine_() >> 11) * 0x1.0p-53;
}

double SeededRandom::normal() {
  if (has_spare_) {
    has_spare_ = false;
    return spare_;
  }
  // Box-Muller; 1 - u keeps the logarithm's argument in (0, 1].
  const double u1 = 1.0 - uniform();
  const double u2 = uniform();
  const double r = std::sqrt(-2.0 * std::log(u1));
  const double a = 2.0 * std::numbers::pi * u2;
  spare_ = r * std::sin(a);
  has_spare_ = true;
  return r * std::cos(a);
}

double z2(const std::vector<double>& heights, double grid, double interval) {
  if (heights.size() < 2 || !(grid > 0.0) || !(interval > 0.0)) return 0.0;
  const double length = grid * static_cast<double>(heights.size() - 1);
  const auto n = static_cast<std::size_t>(std::floor(length / interval + 1e-9));
  if (n < 1) return 0.0;
  auto at = [&](double x) {
    const double f = x / grid;
    auto j = static_cast<std::size_t>(f);
    if (j >= heights.size() - 1) return heights.back();
    const double w = f - static_cast<double>(j);
    return heights[j] + w * (heights[j + 1] - heights[j]);
  };
  double sum = 0.0, prev = at(0.0);
  for (std::size_t j = 1; j <= n; ++j) {
    const double z = at(static_cast<double>(j) * interval);
    const double slope = (z - prev) / interval;
    sum += slope * slope;
    prev = z;
  }
  return std::sqrt(sum / static_cast<double>(n));
}

double jrc_from_z2(double z2_value) { return 32.2 + 32.47 * std::log10(z2_value); }
double z2_from_jrc(double jrc) { return std::pow(10.0, (jrc - 32.2) / 32.47); }

double rms_height_difference(const std::vector<double>& heights, std::size_t lag_points) {
  if (lag_points == 0 || heights.size() <= lag_points) return 0.0;
  double sum = 0.0;
  const std::size_t n = heights.size() - lag_points;
  for (std::size_t j = 0; j < n; ++j) {
    const double d = heights[j + lag_points] - heights[j];
    sum += d * d;
  }
  return std::sqrt(sum / static_cast<double>(n));
}

ProfilePair make_profile_pair(const ProfileSpec& s) {
  const std::string who = "virtual-lab profile: ";
  if (!(s.length > 0.0) || !(s.grid > 0.0) || s.grid * 4.0 > s.length) {
    throw InputError(who + "needs length > 0 and grid > 0 with at least 4 grid steps along the length");
  }
  if (!(s.hurst > 0.0 && s.hurst <= 1.0)) throw InputError(who + "hurst must be in (0, 1]");
  if (!(s.min_wavelength >= 2.0 * s.grid)) {
    throw InputError(who + "min_wavelength must be at least two grid steps (" + std::to_string(2e3 * s.grid) + " mm)");
  }
  if (!(s.max_wavelength > s.min_wavelength)) throw InputError(who + "max_wavelength must exceed min_wavelength");
  if (!(s.jrc > 0.0 && s.jrc <= 32.2 + 32.47 * std::log10(1.5))) {
    throw InputError(who + "jrc must be in (0, 37.9] (Z2 up to 1.5)");
  }
  const auto n_points = static_cast<std::size_t>(std::llround(s.length / s.grid)) + 1;
  // The sum is periodic over P = the profile length; its modes n span the wavelength range.
  const double period = s.grid * static_cast<double>(n_points - 1);
  const auto n_lo = static_cast<long>(std::max(1.0, std::ceil(period / std::min(s.max_wavelength, period) - 1e-9)));
  const auto n_hi = static_cast<long>(std::floor(period / s.min_wavelength + 1e-9));
  if (n_hi < n_lo) throw InputError(who + "no wavelength of the range fits the profile length");
  SeededRandom rng(s.seed);
  SeededRandom rng_upper(s.seed ^ 0xD1B54A32D192ED03ULL);  // independent stream for the mismatch
  ProfilePair out;
  out.lower.assign(n_points, 0.0);
  out.upper.assign(n_points, 0.0);
  auto add = [&](std::vector<double>& z, double k, double amp, double phase) {
    // exp(i (k x_j + phase)) by rotation: one complex product per point instead of a sine.
    const std::complex<double> step = std::polar(1.0, k * s.grid);
    std::complex<double> w = std::polar(amp, phase);
    for (std::size_t j = 0; j < n_points; ++j) {
      z[j] += w.imag();
      w *= step;
    }
  };
  for (long n = n_lo; n <= n_hi; ++n) {
    const double k = 2.0 * std::numbers::pi * static_cast<double>(n) / period;
    const double amp = std::pow(k, -(s.hurst + 0.5));
    const double phase = 2.0 * std::numbers::pi * rng.uniform();
    add(out.lower, k, amp, phase);
    const bool mismatched = 2.0 * std::numbers::pi / k < s.mismatch_wavelength;
    add(out.upper, k, amp, mismatched ? 2.0 * std::numbers::pi * rng_upper.uniform() : phase);
  }
  for (auto* z : {&out.lower, &out.upper}) {
    double mean = 0.0;
    for (double v : *z) mean += v;
    mean /= static_cast<double>(n_points);
    for (double& v : *z) v -= mean;
  }
  const double scale = z2_from_jrc(s.jrc) / z2(out.lower, s.grid);
  for (auto* z : {&out.lower, &out.upper})
    for (double& v : *z) v *= scale;
  return out;
}

std::vector<double> make_profile(const ProfileSpec& s) { return make_profile_pair(s).lower; }

}  // namespace rockdem::vlab
