// mismatch_hardening: a test-only effect plug-in, in no catalogue (registered in the test binary
// only, not in `rockdem`). Hypothesis: once the walls leave the mated position, they touch on
// fewer, mismatched asperity tips that interlock and plough, so the mobilised friction angle grows
// with the distance from the mated position and saturates; back at the mated position the walls
// re-mate and the gain vanishes:
//   alpha = atan(strength / sigma_n) + g |u| / (|u| + u_h),   strength' = sigma_n tan(alpha)
// with u the offset from the mated position at the start of the increment. Its signature in a
// cyclic record is a shear-stress misfit of the base law that follows the offset |u| alone (the
// same on the way out and on the way back, in both cycles and at both normal stresses), which is
// what tests/verification/test_blind_new_effect.cpp asks `diagnose` to find before the effect is
// known to it. Nothing in the catalogue models it (docs/theory/effects.md).
#include <algorithm>
#include <cmath>

#include "framework/plugin_api/effect.hpp"

namespace rockdem::test_plugins {

struct MismatchHardening {
  static constexpr const char* name = "mismatch_hardening";
  struct Params {
    bool enabled;
    double gain;
    double scale;
    static std::vector<Param<Params>> spec() {
      return {
          flag("enabled", &Params::enabled, true, "apply the effect; false leaves the base law unchanged, bit for bit"),
          real("gain", &Params::gain, Dimension::angle,
               "g: friction angle gained far from the mated position (the saturation value)")
              .non_negative()
              .max(0.5)
              .def(0.1),
          real("scale", &Params::scale, Dimension::length, "u_h: offset at which half of the gain is mobilised")
              .positive()
              .def(5e-3),
      };
    }
  };
  struct State {};  // a function of the current offset only
  static void init(const Params&, State&) {}
  static void modify(const Params& p, State&, ShearContext& ctx) {
    if (!(ctx.sigma_n > 0.0) || !(ctx.strength > 0.0)) return;
    const double x = std::abs(ctx.u_s);
    const double alpha = std::atan(ctx.strength / ctx.sigma_n) + p.gain * x / (x + p.scale);
    ctx.strength = ctx.sigma_n * std::tan(std::min(alpha, 1.4));
  }
  static void after(const Params&, State&, const ShearContext&, const JointResponse&) {}
  // A physical hypothesis, so once written it belongs in diagnose's catalogue (the blind test
  // leaves it out by name until then). No `unjudgeable` rule: any record that moves the joint off
  // the mated position can show it. Nothing fixed by default: both parameters are fitted.
  static constexpr bool physical = true;
};

}  // namespace rockdem::test_plugins

ROCKDEM_REGISTER_EFFECT(rockdem::test_plugins::MismatchHardening,
                        "TEST-ONLY plug-in: the friction angle grows with the offset from the mated position, "
                        "phi + g |u|/(|u| + u_h)",
                        "hypothetical, written for the blind test of a new effect (tests/verification/"
                        "test_blind_new_effect.cpp)")
