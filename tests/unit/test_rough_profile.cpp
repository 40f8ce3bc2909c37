// Virtual lab: rough profiles (Tse & Cruden's Z2-JRC relation, seeds, self-affine scaling) and
// the shear box's contact mechanics against closed forms (flat: Coulomb; sawtooth: Patton).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "framework/lab/virtual_lab/rough_profile.hpp"
#include "framework/lab/virtual_lab/shear_box.hpp"

using namespace rockdem;
using namespace rockdem::vlab;

namespace {
constexpr double kDeg = std::numbers::pi / 180.0;
}

TEST(RoughProfile, TseCrudenRelationAndItsInverse) {
  // JRC = 32.2 + 32.47 log10(Z2): Z2 = 1 gives 32.2, Z2 = 0.1 gives -0.27.
  EXPECT_NEAR(jrc_from_z2(1.0), 32.2, 1e-12);
  EXPECT_NEAR(jrc_from_z2(0.1), 32.2 - 32.47, 1e-12);
  for (double jrc : {2.0, 7.0, 12.1, 19.5}) EXPECT_NEAR(jrc_from_z2(z2_from_jrc(jrc)), jrc, 1e-12);
  // A straight line of slope 0.2 has Z2 = 0.2 at any sampling interval.
  std::vector<double> line(1001);
  for (std::size_t j = 0; j < line.size(); ++j) line[j] = 0.2 * 0.1e-3 * static_cast<double>(j);
  EXPECT_NEAR(z2(line, 0.1e-3), 0.2, 1e-12);
}

TEST(RoughProfile, GeneratedProfileHasTheTargetJrc) {
  for (double jrc : {5.0, 11.0, 19.5}) {
    ProfileSpec s;
    s.jrc = jrc;
    s.seed = 3;
    const auto z = make_profile(s);
    EXPECT_NEAR(jrc_from_z2(z2(z, s.grid)), jrc, 1e-9);
    EXPECT_EQ(z.size(), static_cast<std::size_t>(std::llround(s.length / s.grid)) + 1);
  }
}

TEST(RoughProfile, SameSeedSameProfileBitForBitOtherSeedAnother) {
  ProfileSpec s;
  s.seed = 42;
  const auto a = make_profile(s), b = make_profile(s);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t j = 0; j < a.size(); ++j) ASSERT_EQ(a[j], b[j]) << j;
  s.seed = 43;
  const auto c = make_profile(s);
  double diff = 0.0;
  for (std::size_t j = 0; j < a.size(); ++j) diff = std::max(diff, std::abs(a[j] - c[j]));
  EXPECT_GT(diff, 1e-5);
  SeededRandom r1(7), r2(7);
  for (int k = 0; k < 100; ++k) ASSERT_EQ(r1.normal(), r2.normal());
}

// A self-affine profile's rms height difference over a lag d grows as d^H: the log-log slope
// between lags of 4 and 32 mm (well inside the 1..1000 mm band) recovers the Hurst exponent.
TEST(RoughProfile, StructureFunctionScalesWithTheHurstExponent) {
  for (double hurst : {0.5, 0.8}) {
    double slope_sum = 0.0;
    const int seeds = 6;
    for (int seed = 1; seed <= seeds; ++seed) {
      ProfileSpec s;
      s.hurst = hurst;
      s.length = 1.0;
      s.max_wavelength = 1.0;
      s.seed = static_cast<std::uint64_t>(seed);
      const auto z = make_profile(s);
      const double r4 = rms_height_difference(z, 20), r32 = rms_height_difference(z, 160);
      slope_sum += std::log(r32 / r4) / std::log(8.0);
    }
    EXPECT_NEAR(slope_sum / seeds, hurst, 0.08) << "H = " << hurst;
  }
}

TEST(RoughProfile, MismatchedWallsShareOnlyTheLongWavelengths) {
  ProfileSpec s;
  s.mismatch_wavelength = 5e-3;
  const auto p = make_profile_pair(s);
  double d_short = 0.0;  // largest wall difference: from the short, mismatched components only
  for (std::size_t j = 0; j < p.lower.size(); ++j) d_short = std::max(d_short, std::abs(p.lower[j] - p.upper[j]));
  EXPECT_GT(d_short, 1e-6);
  // Differences over 50 mm lags are much larger on each wall than between the walls.
  EXPECT_GT(rms_height_difference(p.lower, 250), 5.0 * d_short);
  s.mismatch_wavelength = 0.0;
  const auto q = make_profile_pair(s);
  for (std::size_t j = 0; j < q.lower.size(); ++j) ASSERT_EQ(q.lower[j], q.upper[j]);
}

TEST(RoughProfile, BadSpecsAreInputErrors) {
  ProfileSpec s;
  s.min_wavelength = s.grid;  // below two grid steps
  EXPECT_THROW(make_profile(s), InputError);
  s = ProfileSpec{};
  s.hurst = 1.5;
  EXPECT_THROW(make_profile(s), InputError);
  s = ProfileSpec{};
  s.jrc = 0.0;
  EXPECT_THROW(make_profile(s), InputError);
}

namespace {

BoxParams plain_box(double phi_deg) {
  BoxParams p;
  p.friction = phi_deg * kDeg;
  p.contact_stiffness = 2e12;
  p.shear_stiffness = 10e9;
  p.wall_strength = 1e12;  // no crushing
  p.wear_coefficient = 0.0;
  p.max_angle = 85 * kDeg;
  p.output_interval = 1e9;
  return p;
}

}  // namespace

// Flat walls: every contact is horizontal, so tau = sigma tan(phi) exactly, both ways.
TEST(ShearBoxContact, FlatWallsArePureCoulomb) {
  const std::vector<double> flat(1526, 0.0);
  ShearBox box(matched_surfaces(flat, 0.2e-3, 0.2032), plain_box(35.0));
  box.set_normal_stress(3e6);
  for (double s : {0.0, 1.3e-3, 7.77e-3, -4.1e-3}) {
    const Resistance r = box.resistance(s);
    EXPECT_NEAR(r.tau_forward, 3e6 * std::tan(35 * kDeg), 1e-9 * 3e6);
    EXPECT_NEAR(r.tau_backward, -3e6 * std::tan(35 * kDeg), 1e-9 * 3e6);
    EXPECT_NEAR(r.contact_fraction, 1.0, 1e-12);
  }
  // Driven through a cycle: elastic with ks, then the Coulomb plateau, then back.
  MeasurementFile f;
  ElementStage st;
  st.normal_stress = 3e6;
  st.path = ShearPath::cycles(2e-3, 1, 1e-4, false);
  BoxParams p = plain_box(35.0);
  p.output_interval = 0.1;
  ShearBox driven(matched_surfaces(flat, 0.2e-3, 0.2032), p);
  driven.run({st}, f);
  double tmax = 0.0, tmin = 0.0;
  for (const auto& r : f.rows) {
    tmax = std::max(tmax, r.shear_stress_MPa);
    tmin = std::min(tmin, r.shear_stress_MPa);
    EXPECT_NEAR(r.normal_disp_mm, 0.0, 1e-12);  // no dilation on flat walls
  }
  EXPECT_NEAR(tmax, 3.0 * std::tan(35 * kDeg), 1e-8);
  EXPECT_NEAR(tmin, -3.0 * std::tan(35 * kDeg), 1e-8);
}

// One sawtooth (a long ramp of inclination i up to a crest, then down): while the top climbs the
// ramp, every contact lies on it and tau = sigma tan(phi + i) (Patton 1966); backwards at the same
// offset the resistance is sigma tan(i - phi); the top rises by the offset times tan i.
TEST(ShearBoxContact, SingleSawtoothGivesPattonWhileClimbing) {
  const double grid = 0.2e-3, i = 10 * kDeg, phi = 30 * kDeg;
  const std::size_t n = 1526;
  std::vector<double> tooth(n);
  const double crest = grid * static_cast<double>(n - 1) - 0.01;  // 36 mm past the top's right end
  for (std::size_t j = 0; j < n; ++j) {
    const double x = grid * static_cast<double>(j);
    tooth[j] = std::tan(i) * (x < crest ? x : 2.0 * crest - x);
  }
  ShearBox box(matched_surfaces(tooth, grid, 0.2032), plain_box(30.0));
  box.set_normal_stress(2e6);
  const double lift0 = box.resistance(0.0).lift;
  for (double s : {0.5e-3, 1.0e-3, 3.7e-3}) {
    const Resistance r = box.resistance(s);
    EXPECT_NEAR(r.tau_forward, 2e6 * std::tan(phi + i), 1e-9 * 2e6) << s;
    EXPECT_NEAR(r.tau_backward, 2e6 * std::tan(i - phi), 1e-9 * 2e6) << s;
    EXPECT_NEAR(r.lift - lift0, s * std::tan(i), 1e-9) << s;
  }
}

TEST(ShearBoxContact, ConstantNormalStiffnessStagesAreRefused) {
  const std::vector<double> flat(1526, 0.0);
  ShearBox box(matched_surfaces(flat, 0.2e-3, 0.2032), plain_box(35.0));
  ElementStage st;
  st.normal_stress = 1e6;
  st.control = NormalControl::constant_stiffness;
  st.normal_stiffness = 1e9;
  st.path = ShearPath::cycles(1e-3, 1, 1e-4);
  MeasurementFile f;
  EXPECT_THROW(box.run({st}, f), InputError);
}
