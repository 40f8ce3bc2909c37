// two_order_roughness: a joint surface has waviness (first-order asperities, long wavelength) and
// unevenness (second-order asperities, short and steep; Patton 1966; Barton 1973). The
// second-order ones control the peak and are sheared off within a fraction of a millimetre of
// it; the first-order ones survive many cycles and wear slowly, with the energy dissipated in
// sliding (plastic work; Plesha 1987; Qiu et al. 1993). The effect adds to the angle of the
// base law's strength
//   delta = i2 exp(-S/s2) - i1 (1 - exp(-W/W1)),      tau = sigma_n tan(alpha + delta),
// alpha = atan(strength/sigma_n) the base law's mobilised angle (after earlier effects), S the
// base law's plastic slip measure accumulated while its roughness angle is not rising (so that a law that
// mobilises its roughness before its peak, Barton-Bandis, keeps the second-order asperities up to
// that peak; Mohr-Coulomb and Continuously-Yielding count from the first slip), W the plastic work
// dissipated (sum of tau du_s^p). i2 raises the first peak and is gone a few s2 past it; i1 is the
// share of the base law's roughness that wears away as W grows past W1 over many cycles. The
// angle is kept in [0, 80 deg]. S and W are those before the increment (explicit).
#include <algorithm>
#include <cmath>
#include <numbers>

#include "framework/plugin_api/effect.hpp"

namespace rockdem {

struct TwoOrderRoughness {
  static constexpr const char* name = "two_order_roughness";
  struct Params {
    bool enabled;
    double i2, s2, i1, w1;
    static std::vector<Param<Params>> spec() {
      using P = Params;
      return {
          flag("enabled", &P::enabled, true, "apply the effect; false leaves the base law unchanged, bit for bit"),
          real("second_order_angle", &P::i2, Dimension::angle,
               "i2: extra angle of the steep second-order asperities on the fresh surface (raises the first peak)")
              .non_negative()
              .max(std::numbers::pi / 4)
              .def(10.0 * std::numbers::pi / 180.0),
          real("second_order_slip", &P::s2, Dimension::length,
               "s2: slip over which the second-order asperities are sheared off (e-folding length)")
              .positive()
              .def(0.5e-3),
          real("first_order_loss", &P::i1, Dimension::angle,
               "i1: angle of first-order roughness lost when the joint is fully worn")
              .non_negative()
              .max(std::numbers::pi / 4)
              .def(5.0 * std::numbers::pi / 180.0),
          real("first_order_work", &P::w1, Dimension::energy_per_area,
               "W1: plastic work per unit area over which the first-order roughness wears (e-folding; a "
               "10 mm cycle at 3 MPa dissipates about 50 kJ/m^2)")
              .positive()
              .def(5e5),
      };
    }
  };
  struct State {
    double slip;        // S: the base law's plastic slip measure accumulated past its peak [m]
    double last_slip;   // its value seen at the last update [m]
    double last_roughness;  // the base law's roughness angle at the last update [rad]
    double work;        // W: plastic work dissipated [J/m^2]
  };
  static void init(const Params&, State& s) { s = State{}; }
  static std::string unjudgeable(const RecordFeatures& f) {
    if (f.cycles < 2) return "a single stroke: the slow first-order wear over repeated shearing cannot be told from the second-order peak";
    return {};
  }
  static void modify(const Params& p, State& s, ShearContext& ctx) {
    if (!(ctx.sigma_n > 0.0)) return;
    const double alpha = std::atan(ctx.strength / ctx.sigma_n);
    // "Rising" is judged on the law's roughness angle, which the laws evaluate from the state at
    // the start of the increment: a test on alpha (from the trial normal stress) would switch with
    // the normal displacement the element driver is solving for, and make the strength jump.
    if (ctx.roughness_angle <= s.last_roughness) s.slip += std::max(0.0, ctx.plastic_slip - s.last_slip);
    s.last_slip = ctx.plastic_slip;
    s.last_roughness = ctx.roughness_angle;
    const double delta = p.i2 * std::exp(-s.slip / p.s2) - p.i1 * (1.0 - std::exp(-s.work / p.w1));
    constexpr double kMaxAngle = 80.0 * std::numbers::pi / 180.0;
    ctx.strength = ctx.sigma_n * std::tan(std::clamp(alpha + delta, 0.0, kMaxAngle));
  }
  static void after(const Params&, State& s, const ShearContext&, const JointResponse& r) {
    s.work += std::max(0.0, r.dissipated);
  }
};

}  // namespace rockdem

ROCKDEM_REGISTER_EFFECT(rockdem::TwoOrderRoughness,
                        "second-order asperities sheared off near the first peak, first-order roughness wearing "
                        "slowly with plastic work over many cycles",
                        "Patton (1966); Barton (1973) Eng. Geol. 7:287-332; Plesha (1987) IJNAMG 11(4); Qiu, Plesha, Huang & Haimson "
                        "(1993) IJRMMS 30(3)")
