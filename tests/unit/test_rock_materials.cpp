#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include <Eigen/Dense>

#include "models/rock/elastic.hpp"
#include "models/rock/mohr_coulomb_rock.hpp"

using namespace rockdem;

namespace {
RawValues raw(std::initializer_list<std::pair<const std::string, std::string>> kv) {
  RawValues v;
  for (const auto& [k, s] : kv) v[k] = RawValue{s, "test.toml key " + k};
  return v;
}
constexpr double kDeg = std::numbers::pi / 180.0;

// Principal stresses (s1 <= s2 <= s3) of an in-plane stress plus szz.
std::array<double, 3> principal(const Voigt3& s, double szz) {
  const double c = 0.5 * (s[0] + s[1]), r = std::hypot(0.5 * (s[0] - s[1]), s[2]);
  std::array<double, 3> p{c - r, c + r, szz};
  std::sort(p.begin(), p.end());
  return p;
}
}  // namespace

TEST(RockMaterials, RegisteredWithTypedParameters) {
  auto& reg = RockMaterialRegistry::instance();
  const auto& e = reg.get("elastic", "rock material", "test");
  auto mat = e.make(raw({{"density", "2420 kg/m3"}, {"bulk", "21443 MPa"}, {"shear", "16083 MPa"}}), "test");
  EXPECT_DOUBLE_EQ(mat->density(), 2420.0);
  EXPECT_DOUBLE_EQ(mat->bulk_modulus(), 21443e6);
  EXPECT_DOUBLE_EQ(mat->shear_modulus(), 16083e6);
  // Unit-less, nonphysical and missing values stop with the key named.
  EXPECT_THROW(e.make(raw({{"density", "2420"}, {"bulk", "1 GPa"}, {"shear", "1 GPa"}}), "t"), InputError);
  EXPECT_THROW(e.make(raw({{"density", "0 kg/m3"}, {"bulk", "1 GPa"}, {"shear", "1 GPa"}}), "t"), InputError);
  EXPECT_THROW(e.make(raw({{"density", "1 kg/m3"}, {"bulk", "-1 GPa"}, {"shear", "1 GPa"}}), "t"), InputError);
  EXPECT_THROW(e.make(raw({{"density", "1 kg/m3"}, {"bulk", "1 GPa"}}), "t"), InputError);

  const auto& mc = reg.get("mohr_coulomb_rock", "rock material", "test");
  const auto base = raw({{"density", "2420 kg/m3"}, {"bulk", "20 GPa"}, {"shear", "12 GPa"}, {"cohesion", "5 MPa"}});
  auto with = [&](std::string k, std::string v) {
    RawValues r = base;
    r[k] = RawValue{v, "test.toml key " + k};
    return r;
  };
  EXPECT_NO_THROW(mc.make(with("friction", "35 deg"), "t"));
  EXPECT_THROW(mc.make(with("friction", "90 deg"), "t"), InputError);
  EXPECT_THROW(mc.make(base, "t"), InputError);  // friction missing
  RawValues dil = with("friction", "30 deg");
  dil["dilation"] = RawValue{std::string("40 deg"), "test.toml key dilation"};
  try {
    mc.make(dil, "t");
    FAIL() << "dilation > friction accepted";
  } catch (const InputError& err) {
    EXPECT_NE(std::string(err.what()).find("dilation"), std::string::npos) << err.what();
  }
}

TEST(RockMaterials, ElasticPlaneStrainClosedForm) {
  // Uniaxial strain exx = e (plane strain): sxx = (K + 4G/3) e, syy = szz = (K - 2G/3) e.
  const ElasticRock::Params p{2420.0, 21443e6, 16083e6};
  ElasticRock::State s{};
  Voigt3 sig = Voigt3::Zero();
  double szz = 0.0;
  const double e = 1e-4;
  for (int i = 0; i < 10; ++i) ElasticRock::update(p, s, Voigt3(e / 10, 0, 0), sig, szz);
  EXPECT_NEAR(sig[0], (p.bulk + 4 * p.shear / 3) * e, 1e-6);
  EXPECT_NEAR(sig[1], (p.bulk - 2 * p.shear / 3) * e, 1e-6);
  EXPECT_NEAR(szz, (p.bulk - 2 * p.shear / 3) * e, 1e-6);
  EXPECT_NEAR(sig[2], 0.0, 1e-9);
  // Simple shear: sxy = G gxy. Plane-strain szz = nu (sxx + syy) for any in-plane path.
  ElasticRock::update(p, s, Voigt3(-3e-5, 2e-5, 5e-5), sig, szz);
  EXPECT_NEAR(sig[2], p.shear * 5e-5, 1e-6);
  const double nu = (3 * p.bulk - 2 * p.shear) / (2 * (3 * p.bulk + p.shear));
  EXPECT_NEAR(szz, nu * (sig[0] + sig[1]), 1e-6 * std::abs(szz));
}

TEST(RockMaterials, MohrCoulombBiaxialCompressionReachesTheEnvelope) {
  // Plane-strain compression under a lateral stress: strain-driven, exy = 0. Start hydrostatic at
  // -p0 (elastic), then shorten in y while holding x stress by a stress-controlled lateral strain.
  MohrCoulombRock::Params p{2500.0, 20e9, 12e9, 35 * kDeg, 5e6, 10 * kDeg, 2e6};
  MohrCoulombRock::State s{};
  const double p0 = 10e6;
  Voigt3 sig(-p0, -p0, 0.0);
  double szz = -p0;
  const double a1 = p.bulk + 4 * p.shear / 3, a2 = p.bulk - 2 * p.shear / 3;
  const double nphi = (1 + std::sin(p.friction)) / (1 - std::sin(p.friction));
  // Closed form peak: s1 = s3 N_phi - 2 c sqrt(N_phi) with s3 = -p0 (the lateral stress) if szz
  // stays intermediate.
  const double s1_peak = -p0 * nphi - 2 * p.cohesion * std::sqrt(nphi);
  bool yielded = false;
  for (int i = 0; i < 4000; ++i) {
    const double dey = -2e-6;
    const double dex = -a2 * dey / a1;  // keeps sxx constant while elastic
    MohrCoulombRock::update(p, s, Voigt3(dex, dey, 0.0), sig, szz);
    for (int k = 0; k < 30; ++k) {  // stress control of the lateral stress by fixed-point corrections
      const double fix = (-p0 - sig[0]) / a1;
      MohrCoulombRock::update(p, s, Voigt3(fix, 0.0, 0.0), sig, szz);
    }
    const auto ps = principal(sig, szz);
    EXPECT_GE(MohrCoulombRock::shear_yield(p, ps[0], ps[2]), -1e-3) << "outside the envelope at " << i;
    if (s.flags & MohrCoulombRock::shear_now) {
      yielded = true;
      EXPECT_NEAR(MohrCoulombRock::shear_yield(p, ps[0], ps[2]), 0.0, 1.0) << "not on the envelope";
    }
  }
  EXPECT_TRUE(yielded);
  EXPECT_NEAR(sig[0], -p0, 100.0);
  EXPECT_NEAR(sig[1], s1_peak, 1e-5 * std::abs(s1_peak));  // perfectly plastic plateau
  EXPECT_NEAR(sig[1], sig[0] * nphi - 2 * p.cohesion * std::sqrt(nphi), 1e-9 * std::abs(s1_peak));
  EXPECT_GT(s.plastic_shear, 0.0);
  EXPECT_EQ(s.plastic_tension, 0.0);
}

TEST(RockMaterials, MohrCoulombDilatancyFollowsThePotential) {
  // At yield under plane-strain compression with fixed lateral stress, the plastic strain ratio
  // is de_lateral^p / de_axial^p = -N_psi (potential g = s1 - s3 N_psi). Measure it from the total
  // strains once the stress has stopped changing (all further strain is plastic).
  for (double psi_deg : {0.0, 15.0, 30.0}) {
    MohrCoulombRock::Params p{2500.0, 20e9, 12e9, 30 * kDeg, 1e6, psi_deg * kDeg, 0.0};
    MohrCoulombRock::State s{};
    const double p0 = 5e6;
    Voigt3 sig(-p0, -p0, 0.0);
    double szz = -p0;
    const double a1 = p.bulk + 4 * p.shear / 3;
    double ex = 0.0, ey = 0.0, ex_y = 0.0, ey_y = 0.0;
    for (int i = 0; i < 3000; ++i) {
      double dex = 0.0;
      const double dey = -1e-6;
      MohrCoulombRock::update(p, s, Voigt3(0, dey, 0), sig, szz);
      for (int k = 0; k < 30; ++k) {  // iterate lateral strain to hold sxx = -p0
        const double fix = (-p0 - sig[0]) / a1;
        MohrCoulombRock::update(p, s, Voigt3(fix, 0, 0), sig, szz);
        dex += fix;
      }
      ex += dex;
      ey += dey;
      if (i == 2000) {
        ex_y = ex;
        ey_y = ey;
      }
    }
    const double npsi = (1 + std::sin(p.dilation)) / (1 - std::sin(p.dilation));
    const double ratio = (ex - ex_y) / (ey - ey_y);
    EXPECT_NEAR(ratio, -npsi, 2e-3 * npsi) << "psi = " << psi_deg;
  }
}

TEST(RockMaterials, MohrCoulombTensionCutOff) {
  MohrCoulombRock::Params p{2500.0, 20e9, 12e9, 40 * kDeg, 8e6, 0.0, 1.5e6};
  EXPECT_DOUBLE_EQ(MohrCoulombRock::tension_cutoff(p), 1.5e6);
  const double a1 = p.bulk + 4 * p.shear / 3, a2 = p.bulk - 2 * p.shear / 3;
  {
    // Uniaxial extension in x: sxx rises to the cut-off and stays; syy, szz keep the elastic
    // increments of the elastic part (FLAC tension correction: s1,2 -= (s3 - s_t) a2/a1).
    MohrCoulombRock::State s{};
    Voigt3 sig = Voigt3::Zero();
    double szz = 0.0;
    double e = 0.0;
    for (int i = 0; i < 200; ++i) {
      MohrCoulombRock::update(p, s, Voigt3(1e-6, 0, 0), sig, szz);
      e += 1e-6;
      EXPECT_LE(sig[0], p.tension * (1 + 1e-12));
    }
    EXPECT_TRUE(s.flags & MohrCoulombRock::tension_now);
    EXPECT_NEAR(sig[0], p.tension, 1e-6);
    EXPECT_NEAR(sig[1], p.tension * a2 / a1, 1e-6);
    EXPECT_NEAR(szz, p.tension * a2 / a1, 1e-6);
    EXPECT_NEAR(s.plastic_tension, e - p.tension / a1, 1e-12);
  }
  {
    // Biaxial extension: two principal stresses held at the cut-off.
    MohrCoulombRock::State s{};
    Voigt3 sig = Voigt3::Zero();
    double szz = 0.0;
    for (int i = 0; i < 200; ++i) MohrCoulombRock::update(p, s, Voigt3(1e-6, 1e-6, 0), sig, szz);
    EXPECT_NEAR(sig[0], p.tension, 1e-6);
    EXPECT_NEAR(sig[1], p.tension, 1e-6);
    EXPECT_LE(szz, p.tension + 1e-6);
  }
  // Tension above the apex is capped at c / tan(phi).
  MohrCoulombRock::Params q = p;
  q.tension = 100e6;
  EXPECT_NEAR(MohrCoulombRock::tension_cutoff(q), q.cohesion / std::tan(q.friction), 1e-6);
}

TEST(RockMaterials, MohrCoulombRandomPathsStayAdmissible) {
  // Random strain jumps, each the elastic strain that would take the current stress to a random
  // target stress in [-40, 10] MPa (so plastic flow cannot shake the path down into the elastic
  // range), crossing the envelope and the cut-off in one step from any side: the returned stress
  // always satisfies f_s >= 0 and s3 <= s_t.
  std::mt19937 rng(12345);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (double psi : {0.0, 20.0}) {
    MohrCoulombRock::Params p{2500.0, 20e9, 12e9, 35 * kDeg, 3e6, psi * kDeg, 1e6};
    MohrCoulombRock::State s{};
    Voigt3 sig = Voigt3::Zero();
    double szz = 0.0;
    int plastic = 0;
    const double a1 = p.bulk + 4 * p.shear / 3, a2 = p.bulk - 2 * p.shear / 3;
    Eigen::Matrix3d d;
    d << a1, a2, 0, a2, a1, 0, 0, 0, p.shear;
    const Eigen::Matrix3d c = d.inverse();
    int shear = 0, tension = 0;
    for (int i = 0; i < 20000; ++i) {
      const Voigt3 target(25e6 * u(rng) - 15e6, 25e6 * u(rng) - 15e6, 15e6 * u(rng));
      MohrCoulombRock::update(p, s, c * (target - sig), sig, szz);
      if (s.flags & MohrCoulombRock::shear_now) ++shear;
      if (s.flags & MohrCoulombRock::tension_now) ++tension;
      const auto ps = principal(sig, szz);
      const double scale = std::max(1e6, std::abs(ps[0]));
      ASSERT_GE(MohrCoulombRock::shear_yield(p, ps[0], ps[2]), -1e-9 * scale) << "step " << i;
      ASSERT_LE(ps[2], MohrCoulombRock::tension_cutoff(p) + 1e-9 * scale) << "step " << i;
      if (s.flags & (MohrCoulombRock::shear_now | MohrCoulombRock::tension_now)) ++plastic;
    }
    EXPECT_GT(plastic, 1000);
    EXPECT_GT(shear, 100);
    EXPECT_GT(tension, 100);
  }
}
