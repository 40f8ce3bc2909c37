#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "models/joint_laws/barton_bandis.hpp"
#include "tests/unit/joint_law_test_util.hpp"

using namespace rockdem;
using namespace rockdem::testutil;

namespace {
constexpr double kDeg = std::numbers::pi / 180.0;
BartonBandis::Params bind_bb(const RawValues& v) { return bind_params<BartonBandis::Params>(v, "bb", "test"); }
}  // namespace

TEST(BartonBandis, ScaleCorrectionsFromLabToFieldLength) {
  const auto p = bind_bb(bb_report({{"jrc", "12"}, {"jcs", "120 MPa"}, {"lab_length", "0.1 m"}, {"field_length", "2 m"}}));
  const auto d = BartonBandis::derive(p);
  EXPECT_NEAR(d.jrc_n, 12.0 * std::pow(20.0, -0.02 * 12.0), 1e-12);
  EXPECT_NEAR(d.jcs_n, 120e6 * std::pow(20.0, -0.03 * 12.0), 1e-3);
  EXPECT_NEAR(d.delta_p, 2.0 / 500.0 * std::pow(d.jrc_n / 2.0, 0.33), 1e-15);  // eq. 3-6
  // Same lengths: no correction.
  const auto q = BartonBandis::derive(bind_bb(bb_report()));
  EXPECT_EQ(q.jrc_n, 7.1);
  EXPECT_EQ(q.jcs_n, 170.5e6);
}

TEST(BartonBandis, JrcMobilisationFollowsBartonsTable) {
  const auto p = bind_bb(bb_report());
  const auto d = BartonBandis::derive(p);
  const double i = 7.1 * std::log10(170.5 / 3.0) * kDeg, phir = 28.4 * kDeg;
  auto mob = [&](double x) { return BartonBandis::mobilised_roughness(p, d, x * d.delta_p, 3e6); };
  EXPECT_NEAR(mob(0.0), -phir, 1e-15);  // JRC_mob/JRC = -phi_r/i: tau = 0 at the start
  EXPECT_NEAR(BartonBandis::strength(p, d, 0.0, 3e6), 0.0, 1e-6);
  EXPECT_NEAR(mob(0.3), 0.0, 1e-15);
  EXPECT_NEAR(mob(0.6), 0.75 * i, 1e-12);
  EXPECT_NEAR(mob(1.0), i, 1e-12);
  EXPECT_NEAR(mob(2.0), 0.85 * i, 1e-12);
  EXPECT_NEAR(mob(4.0), 0.70 * i, 1e-12);
  EXPECT_NEAR(mob(10.0), 0.50 * i, 1e-12);
  EXPECT_NEAR(mob(100.0), 0.0, 1e-15);
  EXPECT_NEAR(mob(1000.0), 0.0, 1e-15);
  EXPECT_NEAR(mob(7.0), 0.60 * i, 1e-12);  // linear between points
  EXPECT_NEAR(mob(0.15), -0.5 * phir, 1e-12);
  // Worn out (delta > 100 delta_p): Mohr-Coulomb with phi_r.
  EXPECT_NEAR(BartonBandis::strength(p, d, 200 * d.delta_p, 3e6), 3e6 * std::tan(phir), 1e-6);
  // sigma_n above JCS: no roughness contribution, no NaN.
  EXPECT_NEAR(BartonBandis::strength(p, d, d.delta_p, 400e6), 400e6 * std::tan(phir), 1e-3);
}

TEST(BartonBandis, DilationAngleIsHalfTheMobilisedRoughnessEq37) {
  auto m = model("barton_bandis", bb_report());
  const auto p = bind_bb(bb_report());
  const auto d = BartonBandis::derive(p);
  ElementDriver drv(*m);
  const ElementStage st = cnl(3e6, ShearPath::cycles(0.01, 1, 1e-4));
  drv.begin_stage(st);
  // Advance to delta/delta_p = 2 and measure the dilation rate over one small step.
  while (drv.response().u_s < 2.0 * d.delta_p) drv.step(st, 1e-6, 0.0);
  const double dil0 = drv.response().dilation;
  const double delta0 = law_state<BartonBandis::State>(drv.state()).delta;
  drv.step(st, 1e-7, 0.0);
  const double rate = (drv.response().dilation - dil0) / 1e-7;
  const double m_rough = BartonBandis::mobilised_roughness(p, d, delta0, 3e6);
  EXPECT_NEAR(rate, std::tan(0.5 * m_rough), 1e-9);
}

TEST(BartonBandis, BandisHyperbolicClosure) {
  const auto p = bind_bb(bb_report({{"normal_closure", "bandis"}, {"ucs", "200.64 MPa"}, {"jrc", "7"}}));
  const auto d = BartonBandis::derive(p);
  const double aj = 7.0 / 5.0 * (0.2 * 200.64 / 170.5 - 0.1);  // mm
  EXPECT_NEAR(d.kni, (-7.15 + 1.75 * 7.0 + 0.02 * 170.5 / aj) * 1e9, 1e-3);
  EXPECT_NEAR(d.vm, (-0.1032 - 0.0074 * 7.0 + 1.135 * std::pow(170.5 / aj, -0.251)) * 1e-3, 1e-15);
  auto m = model("barton_bandis", bb_report({{"normal_closure", "bandis"}, {"ucs", "200.64 MPa"}, {"jrc", "7"}}));
  JointStateBlock s;
  m->init(s);
  JointResponse r;
  JointKinematics k;
  k.du_n = -d.vm / 200.0;
  double last_kn = 0.0, closure = 0.0;
  for (int i = 0; i < 190; ++i) {  // close to 95 % of Vm
    m->update(s, k, r);
    closure += d.vm / 200.0;
    EXPECT_NEAR(r.sigma_n, d.kni * closure / (1.0 - closure / d.vm), 1e-6 * r.sigma_n + 1e-6);
    EXPECT_GT(r.kn, last_kn);  // kn rises with sigma_n
    last_kn = r.kn;
  }
  // Unloading follows the same curve back (elastic closure).
  k.du_n = d.vm / 200.0;
  for (int i = 0; i < 190; ++i) m->update(s, k, r);
  EXPECT_NEAR(r.sigma_n, 0.0, 1e-3);
  // Explicit constants are used as given; without them and without ucs it is an error.
  const auto q = bind_bb(bb_report({{"normal_closure", "bandis"}, {"initial_normal_stiffness", "20 GPa/m"},
                                 {"max_closure", "0.1 mm"}}));
  EXPECT_EQ(BartonBandis::derive(q).kni, 20e9);
  try {
    bind_bb(bb_report({{"normal_closure", "bandis"}}));
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("ucs"), std::string::npos) << e.what();
  }
}

TEST(BartonBandis, StrengthFollowsTheNormalStressUnderConstantNormalStress) {
  // Peak at delta_p for several normal stresses: sigma_n tan(JRC log10(JCS/sigma_n) + phi_r).
  for (double sn : {1e6, 2e6, 5e6}) {
    auto m = model("barton_bandis", bb_report());
    const auto d = BartonBandis::derive(bind_bb(bb_report()));
    ElementOptions o;
    o.max_step = d.delta_p / 50.0;
    ElementDriver drv(*m, o);
    const auto f = drv.run({cnl(sn, ShearPath::cycles(2.0 * d.delta_p, 1, 1e-4, true))});
    const double peak = sn / 1e6 * std::tan((7.1 * std::log10(170.5e6 / sn) + 28.4) * kDeg);
    EXPECT_NEAR(max_tau(f, 0, f.rows.size()), peak, 1e-8) << sn;
  }
}
