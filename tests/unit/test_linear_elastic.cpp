// linear_elastic against its closed form: closed, tau = ks u_s and sigma_n = -kn u_n on any path;
// open (where -kn u_n would be tensile) both are zero, and closing again gives back the stresses of
// the total offsets; nothing is dissipated and a closed path returns exactly to the start (the
// property the drift study's repeated-event check relies on).
#include <gtest/gtest.h>

#include <cmath>

#include "models/joint_laws/linear_elastic.hpp"
#include "tests/unit/joint_law_test_util.hpp"

using namespace rockdem;
using namespace rockdem::testutil;

TEST(LinearElastic, StressesAreTheStiffnessesTimesTheOffsetsOnAnyPath) {
  auto m = model("linear_elastic", values({{"kn", "40 GPa/m"}, {"ks", "10 GPa/m"}}));
  JointStateBlock s;
  m->init(s);
  JointResponse r;
  double us = 0.0, un = 0.0;
  // A wandering path: closure, shear both ways far past any friction limit, opening, shear while
  // open, closing again.
  const double steps[][2] = {{0.0, -5e-5}, {2e-3, 0.0}, {-6e-3, 1e-5}, {3e-3, 6e-5}, {1e-3, -1e-5}, {-2e-3, -4.1e-5}};
  for (const auto& st : steps) {
    for (int i = 0; i < 100; ++i) {
      JointKinematics k;
      k.du_s = st[0] / 100;
      k.du_n = st[1] / 100;
      m->update(s, k, r);
      us += k.du_s;
      un += k.du_n;
      const bool open = un >= 0.0;
      EXPECT_EQ(r.open, open) << "u_n " << un;
      EXPECT_NEAR(r.tau, open ? 0.0 : 10e9 * us, 1e-6 * 10e9 * std::abs(us) + 1e-3);
      EXPECT_NEAR(r.sigma_n, open ? 0.0 : -40e9 * un, 1e-6 * 40e9 * std::abs(un) + 1e-3);
      EXPECT_FALSE(r.slipping);
      EXPECT_EQ(r.dissipated, 0.0);
      EXPECT_EQ(r.kn, 40e9);
      EXPECT_EQ(r.ks, 10e9);
    }
  }
  EXPECT_NEAR(r.sigma_n, 40e9 * 3.1e-5, 1e-3);  // closed again by 0.031 mm
  EXPECT_NEAR(r.tau, 10e9 * -2e-3, 1e-3);     // the total offset's shear stress
  EXPECT_NEAR(r.u_s, us, 1e-15);
  EXPECT_NEAR(r.u_n, un, 1e-15);
}

TEST(LinearElastic, ShearCyclesUnderConstantNormalStressDissipateNothingAndRepeatExactly) {
  auto m = model("linear_elastic", values({{"kn", "30 GPa/m"}, {"ks", "15 GPa/m"}}));
  ElementDriver d(*m);
  const auto f = d.run({cnl(3e6, ShearPath::cycles(0.01, 3, 1e-4))});
  ASSERT_GT(f.rows.size(), 30u);
  for (const auto& row : f.rows) {
    EXPECT_NEAR(row.normal_stress_MPa, 3.0, 1e-9);
    EXPECT_NEAR(row.shear_stress_MPa, 15e9 * row.shear_disp_mm * 1e-3 * 1e-6, 1e-9);  // tau = ks u_s
  }
  // Every cycle passes the same points: the first and the last cycle's rows are the same.
  const std::size_t per = (f.rows.size() - 1) / 3;
  for (std::size_t i = 0; i <= per; ++i)
    EXPECT_NEAR(f.rows[i].shear_stress_MPa, f.rows[i + 2 * per].shear_stress_MPa, 1e-9) << "row " << i;
}
