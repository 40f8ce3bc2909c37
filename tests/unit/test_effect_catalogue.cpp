// The six catalogue effects compose with every base law in one ordered list: the states fit the
// 256-byte block, the record stays finite, the normal solve converges, and `rockdem laws` lists
// them with documented parameters.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "tests/unit/effect_test_util.hpp"

using namespace rockdem;
using namespace rockdem::testutil;

namespace {
std::vector<EffectSpec> all_six() {
  // A closure curve soft enough at 3 MPa (tangent 34 GPa/m) that dilation_recovery's contraction
  // keeps the constrained-displacement response unique (see docs/theory/effects.md, limitations).
  return {effect("hyperbolic_normal_closure", {{"max_closure", "0.5 mm"}}), effect("two_order_roughness"),
          effect("directional_wear", {{"bins", "16"}}), effect("reverse_shear_degradation"),
          effect("dilation_recovery"),                 effect("rate_and_state")};
}
}  // namespace

TEST(EffectCatalogue, AllSixComposeWithEveryLaw) {
  const std::vector<std::pair<const char*, RawValues>> laws = {
      {"mohr_coulomb", mc_report({{"dilation", "reversible"}})}, {"barton_bandis", bb_report()},
      {"continuously_yielding", cy_report()}};
  for (const auto& [law, params] : laws) {
    auto m = model(law, params, all_six());  // throws if the states exceed kJointStateBytes
    EXPECT_EQ(m->effect_count(), 6u);
    ElementDriver d(*m);
    const auto f = d.run({cnl(3e6, ShearPath::cycles(0.005, 2, 1e-4))});
    for (const auto& r : f.rows) {
      ASSERT_TRUE(std::isfinite(r.shear_stress_MPa) && std::isfinite(r.normal_disp_mm)) << law;
      EXPECT_NEAR(r.normal_stress_MPa, 3.0, 1e-6) << law << " at " << r.shear_disp_mm << " mm, t " << r.time_s;
    }
    EXPECT_EQ(d.unconverged_steps(), 0) << law;
    EXPECT_GT(max_tau(f, 0, f.rows.size()), 1.5) << law;
    EXPECT_LT(min_tau(f, 0, f.rows.size()), -1.0) << law;
  }
}

TEST(EffectCatalogue, RegisteredWithDocumentedParameters) {
  for (const char* name : {"reverse_shear_degradation", "dilation_recovery", "directional_wear", "two_order_roughness",
                           "rate_and_state", "hyperbolic_normal_closure"}) {
    const auto* e = EffectRegistry::instance().find(name);
    ASSERT_NE(e, nullptr) << name;
    EXPECT_FALSE(e->summary.empty());
    EXPECT_FALSE(e->reference.empty());
    ASSERT_GE(e->params.size(), 2u) << name;
    EXPECT_EQ(e->params[0].name, "enabled") << name;
    for (const auto& p : e->params) {
      EXPECT_FALSE(p.doc.empty()) << name << "." << p.name;
      EXPECT_FALSE(p.required()) << name << "." << p.name << " has no default";
    }
  }
}

// Each law and effect names in its own file the parameters calibrate keeps fixed; a misspelt
// name would silently leave the parameter free, so every declared name must be one of its own
// real parameters.
TEST(EffectCatalogue, FixedByDefaultNamesRealParameters) {
  auto check = [](const auto& registry, const char* what) {
    for (const auto& [name, entry] : registry.entries()) {
      for (const auto& fixed : entry.declared.fixed_by_default) {
        const bool real = std::any_of(entry.params.begin(), entry.params.end(),
                                      [&](const ParamInfo& p) { return p.name == fixed && p.kind == "real"; });
        EXPECT_TRUE(real) << what << " " << name << " declares '" << fixed << "' fixed by default, not a real parameter of it";
      }
    }
  };
  check(JointLawRegistry::instance(), "law");
  check(EffectRegistry::instance(), "effect");
}
