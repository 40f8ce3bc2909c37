// Pre-loading a contact's joint-law state to an in-situ traction (framework/mechanics/in_situ.hpp)
// for every registered joint law, the nonlinear Bandis closure of barton_bandis and the
// hyperbolic_normal_closure effect included: the law's stresses after the pre-load, and after a
// zero increment (what the engine's first step asks of it), equal the target within 1e-9.
#include <gtest/gtest.h>

#include <string>

#include "framework/mechanics/in_situ.hpp"
#include "framework/model/contact.hpp"

using namespace rockdem;

namespace {

RawValue q(const char* text) { return RawValue{std::string(text), "test"}; }

struct LawCase {
  const char* name;
  std::string law;
  RawValues params;
  std::vector<EffectSpec> effects;
};

std::vector<LawCase> law_cases() {
  return {
      {"coulomb_slip", "coulomb_slip", {{"kn", q("10 GPa/m")}, {"ks", q("5 GPa/m")}, {"friction", q("35 deg")}}, {}},
      {"mohr_coulomb", "mohr_coulomb",
       {{"kn", q("40 GPa/m")}, {"ks", q("12 GPa/m")}, {"friction", q("36 deg")}, {"dilation_angle", q("5 deg")}}, {}},
      {"continuously_yielding", "continuously_yielding",
       {{"kn", q("40 GPa/m")}, {"ks", q("15 GPa/m")}, {"initial_friction", q("50 deg")}, {"friction", q("32 deg")},
        {"roughness", q("3 mm")}}, {}},
      {"barton_bandis (linear)", "barton_bandis",
       {{"kn", q("36 GPa/m")}, {"ks", q("17 GPa/m")}, {"jcs", q("170 MPa")}, {"ucs", q("200 MPa")}, {"jrc", q("7")},
        {"residual_friction", q("28 deg")}, {"lab_length", q("0.2 m")}, {"field_length", q("0.2 m")}}, {}},
      {"barton_bandis (bandis closure)", "barton_bandis",
       {{"kn", q("36 GPa/m")}, {"ks", q("17 GPa/m")}, {"jcs", q("170 MPa")}, {"ucs", q("200 MPa")}, {"jrc", q("7")},
        {"residual_friction", q("28 deg")}, {"lab_length", q("0.2 m")}, {"field_length", q("0.2 m")},
        {"normal_closure", q("bandis")}}, {}},
      {"mohr_coulomb + hyperbolic_normal_closure", "mohr_coulomb",
       {{"kn", q("40 GPa/m")}, {"ks", q("12 GPa/m")}, {"friction", q("36 deg")}},
       {EffectSpec{"hyperbolic_normal_closure", {{"initial_normal_stiffness", q("5 GPa/m")}, {"max_closure", q("0.2 mm")}}, "test"}}},
  };
}

}  // namespace

TEST(InSituPreload, EveryLawCarriesTheTargetStressesWithoutMoving) {
  for (const auto& lc : law_cases()) {
    SCOPED_TRACE(lc.name);
    const auto model = make_joint_model(lc.law, lc.params, lc.effects, "test");
    for (const auto& [sn, tau] : {std::pair{5e6, 1e6}, std::pair{20e6, -3e6}, std::pair{0.3e6, 0.0}}) {
      Contact c;
      c.length = 0.5;
      JointStateBlock state;
      model->init(state);
      bool at_strength = false;
      const double err = preload_contact(c, state.bytes.data(), *model, sn, tau, at_strength);
      EXPECT_FALSE(at_strength);
      EXPECT_LT(err, 1e-9 * sn);
      EXPECT_NEAR(c.response.sigma_n, sn, 1e-9 * sn);
      EXPECT_NEAR(c.response.tau, tau, 1e-9 * sn);
      // The engine's first step: no relative motion, the same stresses.
      JointKinematics k;
      k.length = c.length;
      JointResponse r;
      model->update(state, k, r);
      EXPECT_NEAR(r.sigma_n, sn, 1e-9 * sn);
      EXPECT_NEAR(r.tau, tau, 1e-9 * sn);
    }
  }
}

// A shear target beyond the strength (tau > sigma_n tan 35 deg) stops at the onset of slip.
TEST(InSituPreload, ShearBeyondTheStrengthStopsAtTheStrength) {
  const auto model = make_joint_model("coulomb_slip", {{"kn", q("10 GPa/m")}, {"ks", q("5 GPa/m")}, {"friction", q("35 deg")}},
                                      {}, "test");
  Contact c;
  c.length = 1.0;
  JointStateBlock state;
  model->init(state);
  bool at_strength = false;
  preload_contact(c, state.bytes.data(), *model, 1e6, 2e6, at_strength);
  EXPECT_TRUE(at_strength);
  EXPECT_NEAR(c.response.tau, 1e6 * std::tan(35.0 * 3.14159265358979323846 / 180.0), 1e-6 * 1e6);
}
