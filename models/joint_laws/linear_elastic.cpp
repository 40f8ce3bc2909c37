// linear_elastic: a joint with no strength. Closed, sigma_n = -kn u_n and tau = ks u_s (offsets
// from the unloaded position); it opens without resistance where -kn u_n would be tensile, and
// closes again at the same place with the shear stress of its total offset. The stresses are a
// function of the offsets alone, whatever the path: nothing slips, dilates or is dissipated.
// Not a model of a rock joint: it is the reference against which the other laws' accumulation is
// judged on paths that stay closed. Once a contact opens and closes it is not conservative: the
// offset grows while it is open and the whole shear stress comes back on closing, energy no work
// put in; a shaken drift with it gains energy and blows up (docs/theory/joint_laws.md).
// Why no tension: a joint glued in tension keeps pulling on a corner that the block has carried
// past the end of the edge it was glued to; in cases/drift/small.toml's first earthquake that
// pulled a corner 0.25 m out at 5 GPa and the run went unstable. Effects may be composed with it
// but change nothing: it has no strength or dilation for them to act on.
#include "models/joint_laws/linear_elastic.hpp"

#include "framework/plugin_api/law_support.hpp"

namespace rockdem {

std::vector<Param<LinearElastic::Params>> LinearElastic::Params::spec() {
  using P = Params;
  return {
      real("kn", &P::kn, Dimension::stiffness, "joint normal stiffness (no tension: the joint opens freely)").positive(),
      real("ks", &P::ks, Dimension::stiffness, "joint shear stiffness").positive(),
  };
}

void LinearElastic::update(const Params& p, State& s, const JointKinematics& k, JointResponse& r, EffectChain& chain) {
  s.u_s += k.du_s;
  s.u_n += k.du_n;
  s.elastic_normal -= p.kn * k.du_n;
  s.elastic_shear += p.ks * k.du_s;
  const bool open = s.elastic_normal <= 0.0;
  const double tau_before = s.tau;
  s.sigma_n = open ? 0.0 : s.elastic_normal;
  s.tau = open ? 0.0 : s.elastic_shear;
  // The chain is told of the increment like any law's (effects see a joint that never slips).
  ShearContext ctx;
  ctx.sigma_n = s.sigma_n;
  ctx.u_s = s.u_s - k.du_s;
  ctx.du_s = k.du_s;
  ctx.strength = kInf;
  ctx.dt = k.dt;
  ctx.tau = tau_before;
  ctx.shear_stiffness = p.ks;
  ctx.toward_origin = ctx.u_s * k.du_s < 0.0;
  chain.modify(ctx);
  r.reset();
  r.kn = p.kn;
  r.ks = p.ks;
  law_support::report(s, r);
  r.open = open;
}

}  // namespace rockdem

ROCKDEM_REGISTER_JOINT_LAW(rockdem::LinearElastic,
                           "linear elastic joint with no strength (never slips; opens freely, no tension); "
                           "the reference for what the other laws accumulate",
                           "Goodman, Taylor & Brekke (1968), the joint element's elastic stiffnesses")
