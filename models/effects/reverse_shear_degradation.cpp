// reverse_shear_degradation: on reverse shearing (back toward the mated position) the asperity
// faces climbed on the way out are slid down, so the roughness angle i works against dilation
// instead of with it and the bounding strength uses the basic friction minus the roughness
// angle (Patton 1966's bilinear sawtooth read in reverse; Plesha 1987 makes the same
// distinction between loading and unloading asperity faces):
//   tau_rev = sigma_n tan(max(0, phi_b - w i))   while the increment moves toward the origin,
// never above the base law's own strength. i and phi_b come from the base law through
// ShearContext: psi (Mohr-Coulomb, 0 past u_cs), JRC_mob log10(JCS/sigma_n) (Barton-Bandis),
// phi_m - phi (Continuously-Yielding). w = 1 is Patton's rule; w < 1 a partial loss (gouge
// keeps the faces apart), w > 1 a stronger loss than the base law's roughness implies.
// Addresses the CNWRA report's first finding (sections 2 and 5): the strength on reverse
// shearing is lower than at the end of forward shearing, which none of the three laws gives.
#include <algorithm>
#include <cmath>

#include "framework/plugin_api/effect.hpp"

namespace rockdem {

struct ReverseShearDegradation {
  static constexpr const char* name = "reverse_shear_degradation";
  struct Params {
    bool enabled;
    double weight;
    static std::vector<Param<Params>> spec() {
      return {
          flag("enabled", &Params::enabled, true, "apply the effect; false leaves the base law unchanged, bit for bit"),
          real("weight", &Params::weight, Dimension::dimensionless,
               "w: the reverse friction angle is phi_b - w i (1 = Patton's sawtooth: the faces climbed on the "
               "way out are slid down on the way back)")
              .non_negative()
              .max(10.0)
              .def(1.0),
      };
    }
  };
  struct State {};  // the rule depends only on the current direction and the base law's angles
  static void init(const Params&, State&) {}
  static std::string unjudgeable(const RecordFeatures& f) { return reason_without_reverse_shearing(f); }
  static void modify(const Params& p, State&, ShearContext& ctx) {
    if (!ctx.toward_origin || !(ctx.sigma_n > 0.0)) return;
    const double angle = std::max(0.0, ctx.basic_friction - p.weight * ctx.roughness_angle);
    // Never below the shear stress the joint already carries in the direction it now moves: a
    // joint pre-stressed in shear (the in-situ state of a rock mass) that vibrates about its
    // mated position would otherwise find the bound dropped under its stress, and a law that
    // returns to a lowered bound through a negative tangent (Continuously-Yielding's F < 0, up to
    // -4 ks after a reversal) pumps energy into the contact: a drift model blew up on it. After a
    // real reversal the stress is on the other side (opposite to the motion) and this changes
    // nothing; the lower bound then applies once the stress reaches it.
    const double carried = (ctx.du_s > 0.0 ? 1.0 : -1.0) * ctx.tau;
    ctx.strength = std::min(ctx.strength, std::max(ctx.sigma_n * std::tan(angle), carried));
  }
  static void after(const Params&, State&, const ShearContext&, const JointResponse&) {}
};

}  // namespace rockdem

ROCKDEM_REGISTER_EFFECT(rockdem::ReverseShearDegradation,
                        "reverse shearing slides down the asperity faces climbed on the way out: strength "
                        "sigma_n tan(phi_b - w i) toward the mated position",
                        "Patton (1966) Proc. 1st ISRM Congress 1:509-513; Plesha (1987) IJNAMG 11(4):345-362; "
                        "CNWRA report sections 2 and 5")
