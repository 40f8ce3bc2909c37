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
