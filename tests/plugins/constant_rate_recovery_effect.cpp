// constant_rate_recovery: a test-only effect plug-in, in no catalogue (registered in the test
// binary only, not in `rockdem`), that makes records whose dilation returns along a straight line
// to a residual: from a reversal with dilation d_r, every increment of plastic slip toward the
// mated position gives back dilation at the rate that aims at rho d_r at the origin from where
// the joint stands, (rho d_r - d)/|u_s|. That rate is the same all along the line it draws, so
// the path is straight from where the joint starts sliding back (the elastic part of the
// reversal gives nothing back: no plastic slip) to rho d_r at the origin. It is written as a
// rate, not as a target path as the catalogue's dilation_recovery is (whose line runs from the
// reversal itself and catches up the elastic part's lag), so that
// tests/verification/test_dilation_recovery_shapes.cpp fits the catalogue's effect to a shape
// made by other code (the report's Figures 2-7 and 2-8: the dilation keeps falling on the way
// back and some is left at the origin).
#include <algorithm>
#include <cmath>

#include "framework/plugin_api/effect.hpp"

namespace rockdem::test_plugins {

struct ConstantRateRecovery {
  static constexpr const char* name = "constant_rate_recovery";
  struct Params {
    bool enabled;
    double residual;
    static std::vector<Param<Params>> spec() {
      return {
          flag("enabled", &Params::enabled, true, "apply the effect; false leaves the base law unchanged, bit for bit"),
          real("residual", &Params::residual, Dimension::dimensionless,
               "rho: the dilation left at the mated position, as a fraction of that at the reversal")
              .non_negative()
              .max(1.0)
              .def(0.3),
      };
    }
  };
  struct State {
    double d_rev;   // dilation there [m]
    double d_last;  // the law's dilation after the last update [m]
    bool returning;
  };
  static void init(const Params&, State& s) { s = State{}; }
  static void modify(const Params& p, State& s, ShearContext& ctx) {
    if (ctx.du_s == 0.0) return;
    if (!ctx.toward_origin) {
      s.returning = false;
      return;
    }
    if (!s.returning) {
      s.returning = true;
      s.d_rev = s.d_last;
    }
    if (!(s.d_rev > 0.0) || ctx.u_s == 0.0) return;
    ctx.dilation_rate = std::min(0.0, (p.residual * s.d_rev - s.d_last) / std::abs(ctx.u_s));
  }
  static void after(const Params&, State& s, const ShearContext&, const JointResponse& r) { s.d_last = r.dilation; }
  // A generator of test records, not a hypothesis for diagnose's catalogue.
  static constexpr bool physical = false;
};

}  // namespace rockdem::test_plugins

ROCKDEM_REGISTER_EFFECT(rockdem::test_plugins::ConstantRateRecovery,
                        "TEST-ONLY plug-in: on reverse shearing the dilation falls at a constant rate per plastic slip "
                        "to a residual at the mated position",
                        "written for tests/verification/test_dilation_recovery_shapes.cpp")
