// linear_elastic against its closed form: closed, sigma_n = -kn u_n and tau = ks times the shear
// offset since it last closed; open (where -kn u_n would be tensile) both are zero, the shear
// energy stored at the opening tau^2 / 2 ks is dissipated, and closing again starts the shear from
// zero. While it stays closed nothing is dissipated and a closed path returns exactly to the start
// (the property the drift study's repeated-event check relies on).
#include <gtest/gtest.h>

#include <algorithm>
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
  double us_closed = 0.0;    // the shear offset where the joint last closed (0: closed from the start)
  double tau_before = 0.0;   // the previous increment's shear stress
  double released = 0.0;     // the shear energy released at openings [J/m^2]
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
      if (open) us_closed = us;
      EXPECT_EQ(r.open, open) << "u_n " << un;
      EXPECT_NEAR(r.tau, open ? 0.0 : 10e9 * (us - us_closed), 1e-6 * 10e9 * std::abs(us) + 1e-3);
      EXPECT_NEAR(r.sigma_n, open ? 0.0 : -40e9 * un, 1e-6 * 40e9 * std::abs(un) + 1e-3);
      EXPECT_NEAR(r.dissipated, open ? tau_before * tau_before / (2.0 * 10e9) : 0.0, 1e-9);
      EXPECT_FALSE(r.slipping);
      EXPECT_EQ(r.kn, 40e9);
      EXPECT_EQ(r.ks, 10e9);
      released += r.dissipated;
      tau_before = r.tau;
    }
  }
  // It opened once, during the +3 mm, at tau = ks (-4 mm + 66 x 0.03 mm) = -20.2 MPa.
  EXPECT_NEAR(released, 20.2e6 * 20.2e6 / (2.0 * 10e9), 1e-3);
  EXPECT_NEAR(r.sigma_n, 40e9 * 3.1e-5, 1e-3);  // closed again by 0.031 mm
  EXPECT_NEAR(us_closed, -4.8e-4, 1e-12);       // closed again 0.48 mm into the last -2 mm
  EXPECT_NEAR(r.tau, 10e9 * (us - us_closed), 1e-3);  // only the shear since it closed again
  EXPECT_NEAR(r.u_s, us, 1e-15);
  EXPECT_NEAR(r.u_n, un, 1e-15);
}

// A contact hovering at sigma_n = 0 while its surfaces slide (the drift's near-field corners on
// the far field): each opening releases the shear, so closing never brings back a shear stress
// the joint did not build up since it closed, and no energy comes from nowhere.
TEST(LinearElastic, HoveringAtZeroNormalStressBringsNoShearBack) {
  auto m = model("linear_elastic", values({{"kn", "20 GPa/m"}, {"ks", "10 GPa/m"}}));
  JointStateBlock s;
  m->init(s);
  JointResponse r;
  double largest = 0.0;
  for (int i = 0; i < 1000; ++i) {
    JointKinematics k;
    k.du_s = 1e-5;                          // 10 mm of sliding in all
    k.du_n = (i % 2 == 0 ? -1.0 : 1.0) * 1e-8;  // closing and opening by 0.01 micrometre in turn
    m->update(s, k, r);
    largest = std::max(largest, std::abs(r.tau));
  }
  EXPECT_NEAR(largest, 10e9 * 1e-5, 1e-6);  // one increment's shear at most, not ks x 10 mm = 100 MPa
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
