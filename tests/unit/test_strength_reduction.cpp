#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <numbers>

#include "tests/unit/joint_law_test_util.hpp"

using namespace rockdem;
using namespace rockdem::testutil;

namespace {

std::vector<std::pair<const char*, RawValues>> all_laws() {
  return {{"coulomb_slip", values({{"kn", "35 GPa/m"}, {"ks", "16 GPa/m"}, {"friction", "38 deg"}, {"cohesion", "0.2 MPa"}})},
          {"mohr_coulomb", mc_report({{"dilation", "reversible"}, {"cohesion", "0.27 MPa"}, {"tension", "0.1 MPa"}})},
          {"mohr_coulomb", mc_report({{"dilation", "udec_legacy"}, {"critical_shear_disp", "3 mm"}})},
          {"barton_bandis", bb_report({{"dilation", "reversible"}})},
          {"barton_bandis", bb_report({{"normal_closure", "bandis"}, {"ucs", "200.64 MPa"}})},
          {"continuously_yielding", cy_report({{"dilation", "monotonic"}})}};
}

bool same_bits(const JointResponse& a, const JointResponse& b) {
  const double da[] = {a.sigma_n, a.tau, a.kn, a.ks, a.u_s, a.u_n, a.dilation, a.dissipated};
  const double db[] = {b.sigma_n, b.tau, b.kn, b.ks, b.u_s, b.u_n, b.dilation, b.dissipated};
  return std::memcmp(da, db, sizeof(da)) == 0 && a.slipping == b.slipping && a.open == b.open;
}

}  // namespace

// An effect switched off must leave every law's results identical, bit for bit: stresses, state
// and dissipation, along a path with loading, cycles, separation and re-contact.
TEST(StrengthReduction, DisabledLeavesEveryLawBitForBitIdentical) {
  for (const auto& [law, params] : all_laws()) {
    auto plain = model(law, params);
    auto off = model(law, params,
                     {EffectSpec{"strength_reduction", values({{"enabled", "false"}, {"factor", "2.5"}}), "test"}});
    JointStateBlock sa, sb;
    plain->init(sa);
    off->init(sb);
    JointResponse ra, rb;
    JointKinematics k;
    auto both = [&](double du_n, double du_s) {
      k.du_n = du_n;
      k.du_s = du_s;
      plain->update(sa, k, ra);
      off->update(sb, k, rb);
      ASSERT_TRUE(same_bits(ra, rb)) << law << " du_n " << du_n << " du_s " << du_s;
      const std::size_t n = plain->law().state_size();
      ASSERT_EQ(std::memcmp(sa.bytes.data(), sb.bytes.data(), n), 0) << law;
    };
    both(-1e-4, 0.0);
    for (int cycle = 0; cycle < 2; ++cycle) {
      for (int i = 0; i < 700; ++i) both(0.0, 1e-5);
      for (int i = 0; i < 1400; ++i) both(i % 7 == 0 ? 1e-8 : 0.0, -1e-5);
      for (int i = 0; i < 700; ++i) both(0.0, 1e-5);
    }
    both(2e-3, 0.0);  // separation
    for (int i = 0; i < 50; ++i) both(0.0, 1e-5);
    for (int i = 0; i < 300; ++i) both(-1e-5, 1e-6);  // re-contact
    for (int i = 0; i < 300; ++i) both(0.0, -1e-5);
    EXPECT_GT(ra.dissipated + 1.0, 0.0);
  }
}

TEST(StrengthReduction, DividesTheStrengthByTheFactor) {
  // Mohr-Coulomb without dilation: the plateau is exactly sigma_n tan(phi) / SRF.
  auto m = model("mohr_coulomb", mc_report({{"dilation_angle", "0 deg"}}),
                 {EffectSpec{"strength_reduction", values({{"factor", "1.6"}}), "test"}});
  ElementDriver d(*m);
  const auto f = d.run({cnl(3e6, ShearPath::cycles(0.01, 1, 1e-4))});
  const double expected = 3.0 * std::tan(38.0 * std::numbers::pi / 180.0) / 1.6;
  EXPECT_NEAR(max_tau(f, 0, f.rows.size()), expected, 1e-9);
  EXPECT_NEAR(min_tau(f, 0, f.rows.size()), -expected, 1e-9);
  // With dilation, under constant normal stress the reduced plateau still holds closely.
  auto md = model("mohr_coulomb", mc_report(), {EffectSpec{"strength_reduction", values({{"factor", "1.6"}}), "test"}});
  ElementDriver dd(*md);
  const auto g = dd.run({cnl(3e6, ShearPath::cycles(0.01, 1, 1e-4))});
  EXPECT_NEAR(max_tau(g, 0, g.rows.size()), expected, 1e-4);
  // Two effects compose in order: two factors of 1.25 and 1.28 make 1.6.
  auto m2 = model("mohr_coulomb", mc_report({{"dilation_angle", "0 deg"}}),
                  {EffectSpec{"strength_reduction", values({{"factor", "1.25"}}), "a"},
                   EffectSpec{"strength_reduction", values({{"factor", "1.28"}}), "b"}});
  ElementDriver d2(*m2);
  const auto h = d2.run({cnl(3e6, ShearPath::cycles(0.01, 1, 1e-4))});
  EXPECT_NEAR(max_tau(h, 0, h.rows.size()), expected, 1e-9);
  EXPECT_EQ(m2->description(), "mohr_coulomb + strength_reduction + strength_reduction");
}

TEST(StrengthReduction, FactorOutOfRangeIsAnErrorWithTheRange) {
  try {
    model("mohr_coulomb", mc_report(), {EffectSpec{"strength_reduction", values({{"factor", "0"}}), "case.toml:9"}});
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("valid range is [0.001, 1000]"), std::string::npos) << e.what();
  }
  try {
    model("mohr_coulomb", mc_report(), {EffectSpec{"no_such_effect", {}, "case.toml:9"}});
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("valid names: strength_reduction"), std::string::npos) << e.what();
  }
}
