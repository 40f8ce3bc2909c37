// strength_reduction: divides the shear strength a base law uses by a strength reduction factor
// (SRF). Searching for the SRF at which a model just fails is the shear strength reduction
// method for the factor of safety of rock slopes and excavations (Dawson, Roth & Drescher 1999;
// used with distinct-element codes since). For Mohr-Coulomb this is exactly (C + sigma_n tan
// phi)/SRF; for Barton-Bandis it scales the mobilised strength, for the continuously-yielding law
// the bounding strength. Dilation is left to the base law.
#include "framework/plugin_api/effect.hpp"

namespace rockdem {

struct StrengthReduction {
  static constexpr const char* name = "strength_reduction";
  struct Params {
    bool enabled;
    double factor;
    static std::vector<Param<Params>> spec() {
      return {
          flag("enabled", &Params::enabled, true, "apply the effect; false leaves the base law unchanged, bit for bit"),
          real("factor", &Params::factor, Dimension::dimensionless,
               "strength reduction factor SRF: the strength is divided by it (1 = unchanged)")
              .min(1e-3)
              .max(1e3)
              .def(1.0),
      };
    }
  };
  struct State {};  // no history: the reduction is a fixed property of the analysis
  static void init(const Params&, State&) {}
  static void modify(const Params& p, State&, ShearContext& ctx) { ctx.strength /= p.factor; }
  static void after(const Params&, State&, const ShearContext&, const JointResponse&) {}
  // A factor-of-safety device, not something a joint does: diagnose never proposes it.
  static constexpr bool physical = false;
};

}  // namespace rockdem

ROCKDEM_REGISTER_EFFECT(rockdem::StrengthReduction,
                        "divides the joint shear strength by a strength reduction factor (factor of safety studies)",
                        "Dawson, Roth & Drescher (1999), Geotechnique 49(6), shear strength reduction method")
