#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "models/joint_laws/mohr_coulomb.hpp"
#include "tests/unit/joint_law_test_util.hpp"

using namespace rockdem;
using namespace rockdem::testutil;

namespace {
constexpr double kDeg = std::numbers::pi / 180.0;
}

TEST(MohrCoulomb, ElasticThenPerfectlyPlasticWithCohesion) {
  auto m = model("mohr_coulomb", values({{"kn", "40 GPa/m"}, {"ks", "10 GPa/m"}, {"friction", "30 deg"},
                                         {"cohesion", "0.5 MPa"}, {"residual_after_failure", "false"}}));
  JointStateBlock s;
  m->init(s);
  JointResponse r;
  JointKinematics k;
  k.du_n = -2e6 / 40e9;  // closure to 2 MPa (eq. 3-2 normal analogue)
  m->update(s, k, r);
  EXPECT_NEAR(r.sigma_n, 2e6, 1e-6);
  k.du_n = 0.0;
  k.du_s = 1e-5;
  m->update(s, k, r);
  EXPECT_NEAR(r.tau, 1e5, 1e-6);  // Ks du
  EXPECT_FALSE(r.slipping);
  EXPECT_EQ(r.dissipated, 0.0);
  for (int i = 0; i < 300; ++i) m->update(s, k, r);
  const double tau_o = 0.5e6 + 2e6 * std::tan(30 * kDeg);  // eq. 3-1
  EXPECT_NEAR(r.tau, tau_o, 1e-6);
  EXPECT_TRUE(r.slipping);
  EXPECT_NEAR(r.dissipated, tau_o * 1e-5, 1e-6);
}

TEST(MohrCoulomb, CohesionAndTensionAreLostAfterFailureWhenResidual) {
  auto m = model("mohr_coulomb", values({{"kn", "40 GPa/m"}, {"ks", "10 GPa/m"}, {"friction", "30 deg"},
                                         {"cohesion", "0.5 MPa"}, {"tension", "0.3 MPa"}}));
  JointStateBlock s;
  m->init(s);
  JointResponse r;
  JointKinematics k;
  // Tension up to the tensile strength is carried...
  k.du_n = 0.25e6 / 40e9;
  m->update(s, k, r);
  EXPECT_NEAR(r.sigma_n, -0.25e6, 1e-6);
  EXPECT_FALSE(r.open);
  // ... beyond it the joint fails in tension: sigma_n becomes zero (report section 3.1).
  k.du_n = 0.1e6 / 40e9;
  m->update(s, k, r);
  EXPECT_TRUE(r.open);
  EXPECT_EQ(r.sigma_n, 0.0);
  EXPECT_EQ(r.tau, 0.0);
  // Closed again and loaded to 2 MPa, the strength is friction only (cohesion lost).
  k.du_n = -0.35e6 / 40e9 - 2e6 / 40e9;
  m->update(s, k, r);
  EXPECT_NEAR(r.sigma_n, 2e6, 1e-3);
  k.du_n = 0.0;
  k.du_s = 1e-5;
  for (int i = 0; i < 300; ++i) m->update(s, k, r);
  EXPECT_NEAR(r.tau, r.sigma_n * std::tan(30 * kDeg), 1e-3);
  // And no tensile strength is left.
  k.du_s = 0.0;
  k.du_n = 2e6 / 40e9 + 1e-9;
  m->update(s, k, r);
  EXPECT_TRUE(r.open);
}

TEST(MohrCoulomb, NoDilationBeforeSlipEq33) {
  auto m = model("mohr_coulomb", mc_report({{"dilation_angle", "10 deg"}}));
  ElementDriver d(*m);
  const ElementStage st = cnl(3e6, ShearPath::cycles(0.01, 1, 1e-4));
  d.begin_stage(st);
  for (int i = 0; i < 13; ++i) {  // 0.13 mm < tau_o/ks = 0.1384 mm: elastic
    d.step(st, 1e-5, 0.0);
    EXPECT_EQ(d.response().dilation, 0.0);
  }
  for (int i = 0; i < 100; ++i) d.step(st, 1e-5, 0.0);
  const double ue = 3e6 * std::tan(38 * kDeg) / 16.93e9;
  EXPECT_NEAR(d.response().dilation, std::tan(10 * kDeg) * (1.13e-3 - ue), 1e-12);
  EXPECT_NEAR(d.normal_disp(), d.response().dilation, 1e-12);  // CNL: the joint opens by its dilation
}

TEST(MohrCoulomb, ParametersAreCheckedWithRangesAndUnits) {
  try {
    model("mohr_coulomb", mc_report({{"friction", "95 deg"}}));
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("valid range is [0 deg, 90 deg)"), std::string::npos) << e.what();
  }
  try {
    model("mohr_coulomb", mc_report({{"dilation", "sometimes"}}));
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("one of {monotonic, reversible, udec_legacy}"), std::string::npos) << e.what();
  }
  EXPECT_THROW(model("mohr_coulomb", mc_report({{"ks", "16.93"}})), InputError);  // no unit
  EXPECT_THROW(model("mohr_coulomb", values({{"ks", "16.93 GPa/m"}})), InputError);  // kn, friction missing
  EXPECT_THROW(model("mohr_coulomb", mc_report({{"jfric", "38 deg"}})), InputError);  // unknown key
}

// A prescribed final normal stress (JointKinematics::sigma_n_given, what the element driver
// hands the law): the update there is the consistent one the law's own solve finds, and the
// normal stress after it moves with du_n at exactly kn, the shear stress not at all (the driver's
// normal solve meets a straight line).
TEST(MohrCoulomb, APrescribedNormalStressGivesTheConsistentUpdateAndAStraightResponse) {
  const double kn = 40e9;
  auto m = model("mohr_coulomb", values({{"kn", "40 GPa/m"}, {"ks", "10 GPa/m"}, {"friction", "30 deg"},
                                         {"dilation_angle", "10 deg"}}));
  JointStateBlock loaded;
  m->init(loaded);
  JointResponse r;
  JointKinematics k;
  k.du_n = -2e6 / kn;
  m->update(loaded, k, r);
  ASSERT_NEAR(r.sigma_n, 2e6, 1e-6);
  k = JointKinematics{};
  k.du_s = 5e-4;  // well past the elastic limit: slips and dilates
  JointStateBlock own = loaded;
  JointResponse r_own;
  m->update(own, k, r_own);  // constrained: the law solves for its consistent stress
  ASSERT_TRUE(r_own.slipping);
  ASSERT_TRUE(r_own.consistent);
  ASSERT_GT(r_own.sigma_n, 2.1e6);  // dilation under constrained normal displacement
  JointStateBlock given = loaded;
  JointResponse r_given;
  k.sigma_n_given = r_own.sigma_n;
  m->update(given, k, r_given);
  EXPECT_NEAR(r_given.sigma_n, r_own.sigma_n, 1e-5);
  EXPECT_NEAR(r_given.tau, r_own.tau, 1e-5);
  EXPECT_NEAR(r_given.dilation, r_own.dilation, 1e-16);
  EXPECT_TRUE(r_given.consistent);
  // Under 2 MPa prescribed, opening probes: the strength stays 2 MPa tan 30 deg, and the normal
  // stress falls by kn per metre of opening.
  k.sigma_n_given = 2e6;
  double last_sigma = 0.0;
  for (int i = 0; i < 5; ++i) {
    JointStateBlock s = loaded;
    k.du_n = 1e-5 * i;
    m->update(s, k, r);
    EXPECT_NEAR(r.tau, 2e6 * std::tan(30 * kDeg), 1e-6) << i;
    if (i > 0) {
      EXPECT_NEAR(last_sigma - r.sigma_n, kn * 1e-5, 1e-4) << i;
    }
    last_sigma = r.sigma_n;
  }
}
