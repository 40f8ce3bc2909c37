#pragma once
// Helpers for effect tests: the bit-for-bit check that a disabled effect leaves a law unchanged,
// run for every law over a path with loading, cycles, separation and re-contact.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <string>
#include <utility>
#include <vector>

#include "tests/unit/joint_law_test_util.hpp"

namespace rockdem::testutil {

// The laws (and options) an effect must leave untouched when disabled.
inline std::vector<std::pair<const char*, RawValues>> bit_identity_laws() {
  return {{"coulomb_slip", values({{"kn", "35 GPa/m"}, {"ks", "16 GPa/m"}, {"friction", "38 deg"}, {"cohesion", "0.2 MPa"}})},
          {"mohr_coulomb", mc_report({{"dilation", "reversible"}, {"cohesion", "0.27 MPa"}, {"tension", "0.1 MPa"}})},
          {"mohr_coulomb", mc_report({{"dilation", "udec_legacy"}, {"critical_shear_disp", "3 mm"}})},
          {"barton_bandis", bb_report({{"dilation", "reversible"}})},
          {"barton_bandis", bb_report({{"normal_closure", "bandis"}, {"ucs", "200.64 MPa"}})},
          {"continuously_yielding", cy_report({{"dilation", "monotonic"}})}};
}

inline bool same_bits(const JointResponse& a, const JointResponse& b) {
  const double da[] = {a.sigma_n, a.tau, a.kn, a.ks, a.u_s, a.u_n, a.dilation, a.dissipated};
  const double db[] = {b.sigma_n, b.tau, b.kn, b.ks, b.u_s, b.u_n, b.dilation, b.dissipated};
  return std::memcmp(da, db, sizeof(da)) == 0 && a.slipping == b.slipping && a.open == b.open &&
         a.consistent == b.consistent;
}

// Every law with `effects` (all disabled) gives responses and base states identical, bit for
// bit, to the plain law; dt > 0 so that rate-dependent effects would see a velocity.
inline void expect_disabled_is_bit_identical(const std::vector<EffectSpec>& effects) {
  for (const auto& [law, params] : bit_identity_laws()) {
    auto plain = model(law, params);
    auto off = model(law, params, effects);
    EXPECT_EQ(plain->initial_kn(), off->initial_kn()) << law;
    JointStateBlock sa, sb;
    plain->init(sa);
    off->init(sb);
    JointResponse ra, rb;
    JointKinematics k;
    k.dt = 0.01;
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
  }
}

// One effect by name with "key = value" parameters; whole numbers are passed as TOML integers.
inline EffectSpec effect(const std::string& name, std::initializer_list<std::pair<std::string, std::string>> kv = {}) {
  RawValues v = values(kv);
  for (auto& [k, r] : v) {
    const auto* s = std::get_if<std::string>(&r.value);
    if (s && !s->empty() && s->find_first_not_of("0123456789") == std::string::npos) r.value = std::int64_t{std::stoll(*s)};
  }
  return EffectSpec{name, v, "test"};
}

// Index of the first row of the first return stroke (the row after the largest offset).
inline std::size_t first_reverse_row(const MeasurementFile& f) {
  std::size_t i = 0;
  while (i + 1 < f.rows.size() && f.rows[i + 1].shear_disp_mm >= f.rows[i].shear_disp_mm) ++i;
  return i + 1;
}

}  // namespace rockdem::testutil
