// dilation_recovery: on reverse shearing the dilation gained on the way out is given back as the
// block returns toward the mated position, along a path below the forward curve (but for a
// residual's share near the origin, where the forward curve starts from zero), down to zero or
// to a residual left by gouge (CNWRA report section 2, Figures 2-2, 2-7, 2-8: the dilation
// "tends to decrease constantly during reverse shearing and may retain a small amount" at the
// original position; section 5: the laws' sign change of psi recovers far too little). Target
// dilation on the way back from a reversal at offset u_r with dilation d_r, x = |u_s|/|u_r| in
// [0, 1]:
//   d(x) = d_res + (d_r - d_res) g(x),  g(x) = x - h x (1 - x),  d_res = rho d_r
// g is the chord for h = 0 and x^2 for h = 1: the larger h, the faster the first recovery and
// the further below the forward curve (hysteresis). The path ends at the residual at the mated
// position, straight (h = 0) or curved (h = 1, arriving flat), and keeps decreasing all the way.
// (Until 2026-11-29 it was max(d_res, d_r g(x)): the same where rho = 0, but with a residual the
// recovery stopped short of the origin and could not be a straight line ending above zero.)
// The effect sets the base law's dilation rate so that its dilation follows d(x): rate =
// (d(x_end) - d)/|du_s|, never positive (no dilation on the way back) and at most 2 (1 + h)
// d_r/|u_r| in magnitude (twice the steepest slope of d where rho = 0, 2/(1 - rho) times it
// with a residual; with rate_bound = "climb" also no more than 2 (1 + h) times the steepest
// dilation rate met moving away from the origin), so that the lag left by the elastic part of the
// reversal is caught up within a fraction of a millimetre instead of in one jump. Away from the
// origin the base law's rate stands.
#include <algorithm>
#include <cmath>

#include "framework/plugin_api/effect.hpp"

namespace rockdem {

struct DilationRecovery {
  static constexpr const char* name = "dilation_recovery";
  struct Params {
    bool enabled;
    double residual_fraction;
    double hysteresis;
    int rate_bound;  // 0: path, 1: climb
    static std::vector<Param<Params>> spec() {
      return {
          flag("enabled", &Params::enabled, true, "apply the effect; false leaves the base law unchanged, bit for bit"),
          real("residual_fraction", &Params::residual_fraction, Dimension::dimensionless,
               "rho: dilation left at the mated position, as a fraction of the dilation at the reversal (gouge); "
               "0 = full recovery")
              .non_negative()
              .max(1.0)
              .def(0.0),
          real("hysteresis", &Params::hysteresis, Dimension::dimensionless,
               "h: shape of the return path d = d_res + (d_r - d_res) (x - h x (1 - x)), x = |u_s|/|u_reversal|; "
               "0 = a straight line to the residual at the origin, 1 = a parabola arriving flat (well below the "
               "forward curve)")
              .non_negative()
              .max(1.0)
              .def(1.0),
          choice("rate_bound", &Params::rate_bound, {"path", "climb"}, "path",
                 "steepest recovery: 'path', 2 (1 + h) d_r/|u_r|, at least twice the return path's own slope "
                 "(as validated on laboratory records, where dilation gained over many strokes comes back in one); "
                 "'climb', also no steeper than twice (1 + h) the steepest dilation rate met on the way out (for "
                 "rock masses under earthquakes, where contacts vibrate and 'path' couples shear and normal too "
                 "stiffly for a stable step)"),
      };
    }
  };
  struct State {
    double u_rev;   // offset where the current return stroke began [m]
    double d_rev;   // dilation there [m]
    double d_last;  // the base law's dilation after the last update [m]
    float climb;    // the steepest dilation rate met moving away from the mated position (float:
                    // a bound, and the state of a contact with every effect stays within 256 bytes)
    bool returning;
  };
  static void init(const Params&, State& s) { s = State{}; }
  static std::string unjudgeable(const RecordFeatures& f) { return reason_without_reverse_shearing(f); }
  static void modify(const Params& p, State& s, ShearContext& ctx) {
    if (ctx.du_s == 0.0) return;  // a pause changes nothing
    if (!ctx.toward_origin) {
      s.returning = false;
      s.climb = std::max(s.climb, static_cast<float>(ctx.dilation_rate));
      return;
    }
    if (!s.returning) {
      s.returning = true;
      s.u_rev = ctx.u_s;
      s.d_rev = s.d_last;
    }
    const double u_end = ctx.u_s + ctx.du_s;
    const double x = u_end * ctx.u_s <= 0.0 ? 0.0 : std::min(1.0, std::abs(u_end / s.u_rev));
    if (!(s.d_rev > 0.0)) return;
    // Written so that rho = 0 gives d_r g(x) to the bit (0 + 1 * g), the form before 2026-11-29.
    const double rho = p.residual_fraction;
    const double target = s.d_rev * (rho + (1.0 - rho) * (x - p.hysteresis * x * (1.0 - x)));
    // The rate is bounded by at least twice the path's steepest slope, so that the lag left by the
    // elastic part of the reversal is caught up. With rate_bound = "climb" the slope is also no steeper
    // than the steepest climb met on the way out: in a rock mass under an earthquake a contact
    // vibrating a hair from the mated position with dilation left from earlier strokes
    // (|u_rev| ~ 1e-7 m, d_rev ~ 0.1 mm) would otherwise ask for a rate of 1000, a normal-shear
    // coupling a thousand times kn; bounding only such elastic-range reversals was not enough
    // (the small drift study still blew up in its first event).
    double slope = s.d_rev / std::abs(s.u_rev);
    if (p.rate_bound == 1) slope = std::min(slope, static_cast<double>(s.climb));
    const double cap = 2.0 * (1.0 + p.hysteresis) * slope;
    ctx.dilation_rate = std::max(-cap, std::min(0.0, (target - s.d_last) / std::abs(ctx.du_s)));
  }
  static void after(const Params&, State& s, const ShearContext&, const JointResponse& r) { s.d_last = r.dilation; }
};

}  // namespace rockdem

ROCKDEM_REGISTER_EFFECT(rockdem::DilationRecovery,
                        "dilation follows the offset back to the mated position on reverse shearing, below the "
                        "forward curve (hysteresis), to zero or a gouge residual",
                        "CNWRA report sections 2 and 5 (Figures 2-2, 2-7, 2-8); Plesha (1987); Jing, Stephansson & "
                        "Nordlund (1993)")
