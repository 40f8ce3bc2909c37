#pragma once
// Seeded random self-affine joint profiles for the virtual lab (framework/lab/virtual_lab/).
//
// A profile is heights z(x) on a uniform grid, made by spectral synthesis: a sum of sinusoids
// with wavenumbers k = 2 pi n / P between the given longest and shortest wavelengths, random
// phases, and amplitudes a_n ~ k^-(H + 1/2), so that the power spectrum falls as k^-(1 + 2H) and
// the height difference over a lag d grows as d^H (self-affine with Hurst exponent H; Mandelbrot
// 1985, Brown & Scholz 1985 for rock surfaces). The amplitude is then scaled so that the profile's
// Z2 (root-mean-square slope) gives the target JRC through Tse & Cruden (1979):
//     JRC = 32.2 + 32.47 log10(Z2),
// Z2 evaluated, as they did, on heights sampled every 1.27 mm (0.05 in).
// Random numbers come from std::mt19937_64 raw output (fully specified by the standard), so a
// seed gives the same profile bit for bit on any platform with IEEE doubles and the same libm.
#include <cstdint>
#include <random>
#include <vector>

namespace rockdem::vlab {

// Tse & Cruden (1979) sampling interval of their Z2 [m].
inline constexpr double kTseCrudenInterval = 1.27e-3;

struct ProfileSpec {
  double length = 0.305;          // profile length [m]
  double grid = 0.2e-3;           // sampling interval of the stored heights [m]
  double hurst = 0.8;             // Hurst exponent H, 0 < H <= 1
  double min_wavelength = 1e-3;   // shortest wavelength in the sum [m]
  double max_wavelength = 0.305;  // longest wavelength [m] (at most the length)
  double jrc = 10.0;              // target JRC (Tse & Cruden), > 0 and < 32.2 + 32.47 log10(Z2) for Z2 <= 1.5
  std::uint64_t seed = 1;
  // The two walls of a natural joint match at long wavelengths and not at short ones (Brown,
  // Kranz & Bonner 1986): components shorter than this get independent phases on the second wall.
  double mismatch_wavelength = 0.0;  // [m]; 0 = perfectly matched walls
};

// The two walls of one joint: `lower` has the spec's JRC; `upper` shares its components at
// wavelengths >= mismatch_wavelength and has its own phases below (same amplitudes, same scale).
struct ProfilePair {
  std::vector<double> lower, upper;
};
ProfilePair make_profile_pair(const ProfileSpec& spec);

// Z2 = sqrt( mean over the samples of ((z_{j+1} - z_j) / dx)^2 ) of heights resampled (linear
// interpolation) every `interval` [m] along a profile stored every `grid` [m].
double z2(const std::vector<double>& heights, double grid, double interval = kTseCrudenInterval);
// Tse & Cruden (1979) and its inverse.
double jrc_from_z2(double z2_value);
double z2_from_jrc(double jrc);

// Heights [m] at x_j = j * grid, j = 0 .. round(length / grid), mean zero, with Z2 giving spec.jrc.
// Throws InputError when the spec is inconsistent (wavelength range empty or below two grid steps).
std::vector<double> make_profile(const ProfileSpec& spec);

// Root-mean-square height difference over a lag of `lag_points` grid steps (the structure
// function's square root; grows as lag^H for a self-affine profile).
double rms_height_difference(const std::vector<double>& heights, std::size_t lag_points);

// Deterministic random numbers from a seed: uniform in [0, 1) from the top 53 bits of
// mt19937_64, and standard normal by Box-Muller, both independent of the standard library's
// distribution classes (whose algorithms are implementation-defined).
class SeededRandom {
 public:
  explicit SeededRandom(std::uint64_t seed);
  double uniform();
  double normal();

 private:
  std::mt19937_64 engine_;
  bool has_spare_ = false;
  double spare_ = 0.0;
};

}  // namespace rockdem::vlab
