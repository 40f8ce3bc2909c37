// directional_wear: the base laws wear one roughness with all slip, whichever side of the mated
// position it happens on. A block sheared past the origin meets surface it has not slid over
// before: in the report's dynamic tests (section 5.2, Figures 5-32 to 5-38) the third quadrant of
// the first cycle shows a second peak like the first, which UDEC could not represent. Following
// Qiu, Plesha et al. (1993), who track the asperities facing each way apart, the effect keeps the
// wear separately for the two sides of the mated position, and optionally in bins of offset
// along each side (`bins` > 2), and lets the base law's own wear function decide the roughness:
//   S(u) = max(W[bin(u)], P),   i_fresh = i_law(S, sigma_n),
//   while moving away from the origin, if i_fresh > i (the law's current, globally worn angle):
//   strength = sigma_n tan(alpha + i_fresh - i),   dilation rate x tan(i_fresh)/tan(i)
//   (the rate is left alone for a law whose dilation follows its shear stress, CY's eq. 3-16:
//   there the raised strength raises the dilation by itself)
// W[k] is the base law's wear measure (ShearContext::plastic_slip: BB's travel delta, CY's u_s^p,
// MC's plastic slip) gained while climbing away from the origin in bin k; P is that gained in the
// current outward pass (the block's own asperities wear as it goes, so fresh bottom surface met
// late in a pass is not virgin); i_law is ShearContext::roughness_at, the base law's roughness as
// a function of its wear measure (virgin curve, including Barton-Bandis' mobilisation); alpha =
// atan(strength/sigma_n). With two bins S is the wear of the side. Shearing back toward the
// origin is left to the base law (combine with reverse_shear_degradation). Mohr-Coulomb has no
// wear (i_law = psi), so the effect changes nothing there. Wear is stored in float (7 digits).
#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

#include "framework/plugin_api/effect.hpp"

namespace rockdem {

struct DirectionalWear {
  static constexpr const char* name = "directional_wear";
  static constexpr int kMaxBins = 16;
  struct Params {
    bool enabled;
    int bins;
    double extent;
    void validate() const {
      if (bins < 2 || bins > kMaxBins || bins % 2 != 0) {
        throw InputError("effect 'directional_wear': bins must be even, from 2 (the two sides of the mated position) "
                         "to 16; got " + std::to_string(bins));
      }
    }
    static std::vector<Param<Params>> spec() {
      return {
          flag("enabled", &Params::enabled, true, "apply the effect; false leaves the base law unchanged, bit for bit"),
          integer("bins", &Params::bins, 2,
                  "wear bins: 2 = one per side of the mated position; 4..16 (even) = resolved along the surface, "
                  "bins/2 per side over `extent`")
              .min(2)
              .max(kMaxBins),
          real("extent", &Params::extent, Dimension::length,
               "offset covered by the bins on each side (beyond it: the outermost bin); bin width extent/(bins/2) "
               "should exceed the base law's peak displacement")
              .positive()
              .def(25e-3),
      };
    }
  };
  struct State {
    std::array<float, kMaxBins> wear;  // W[k]: base wear measure gained climbing in bin k [m]
    double pass;                       // P: gained in the current outward pass [m]
    double last_slip;                  // base wear measure seen at the last update [m]
    int last_bin;                      // bin of the last update's increment, -1: not climbing
  };
  static void init(const Params&, State& s) {
    s = State{};
    s.last_bin = -1;
  }
  // The extent is the discretisation's reach, not a property of the joint.
  static std::vector<std::string> fixed_by_default() { return {"extent"}; }
  static std::string unjudgeable(const RecordFeatures& f) {
    if (f.negative_side_rows < 5 || f.positive_side_rows < 5) {
      return "the joint is sheared on one side of the mated position only (no passage past the origin onto fresh surface)";
    }
    return {};
  }
  static void modify(const Params& p, State& s, ShearContext& ctx) {
    // The wear the law gained in the last update belongs to where that increment climbed.
    const double gained = ctx.plastic_slip - s.last_slip;
    if (gained > 0.0 && s.last_bin >= 0) {
      s.wear[static_cast<std::size_t>(s.last_bin)] += static_cast<float>(gained);
      s.pass += gained;
    }
    s.last_slip = ctx.plastic_slip;
    if (ctx.du_s == 0.0) return;  // a pause keeps the pass
    const double u_end = ctx.u_s + ctx.du_s;
    if (ctx.toward_origin || u_end == 0.0) {
      s.last_bin = -1;
      s.pass = 0.0;
      return;
    }
    const int per_side = p.bins / 2;
    const int j = std::min(per_side - 1, static_cast<int>(std::abs(u_end) / p.extent * per_side));
    const int bin = u_end > 0.0 ? per_side + j : per_side - 1 - j;
    s.last_bin = bin;
    if (!(ctx.sigma_n > 0.0)) return;
    const double worn = std::max(static_cast<double>(s.wear[static_cast<std::size_t>(bin)]), s.pass);
    const double fresh = ctx.roughness(worn, ctx.sigma_n);
    const double i = ctx.roughness_angle;
    if (!(fresh > i)) return;
    constexpr double kMaxAngle = 80.0 * std::numbers::pi / 180.0;
    const double alpha = std::atan(ctx.strength / ctx.sigma_n);
    ctx.strength = ctx.sigma_n * std::tan(std::min(kMaxAngle, alpha + fresh - i));
    // A law whose dilation follows its shear stress (CY) dilates more on fresh surface through the
    // raised strength already; scaling its rate too made the first pass past the origin dilate
    // 3.2 times the first pass on the other side over 8 mm (10 mm cycles at 3 MPa, the report's CY).
    if (i > 1e-9 && !ctx.dilation_follows_stress) ctx.dilation_rate *= std::tan(fresh) / std::tan(i);
  }
  static void after(const Params&, State&, const ShearContext&, const JointResponse&) {}
};

}  // namespace rockdem

ROCKDEM_REGISTER_EFFECT(rockdem::DirectionalWear,
                        "roughness worn separately on the two sides of the mated position (optionally in bins "
                        "along the surface): fresh surface past the origin gives a second peak",
                        "Qiu, Plesha, Huang & Haimson (1993) IJRMMS 30(3):271-287; CNWRA report section 5.2, "
                        "Figures 5-32 to 5-38")
