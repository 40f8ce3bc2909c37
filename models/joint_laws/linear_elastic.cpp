// linear_elastic: a joint with no strength. Closed, sigma_n = -kn u_n (u_n the offset from the
// unloaded position) and tau = ks times the shear offset since the joint last closed; open (where
// -kn u_n would be tensile) both are zero. While it stays closed the stresses are a function of
// the offsets alone and nothing is dissipated: the reference against which the other laws'
// accumulation is judged. Opening releases the shear: a joint with no normal stress carries no
// shear (Coulomb's bound with any friction), and on closing again the surfaces meet where they
// are, so the shear starts from zero there. The shear energy stored when it opens, tau^2 / 2 ks,
// is reported as dissipated. Until 2026-11-30 it closed with the shear stress of its total
// offset, an energy no work had put in: contacts hovering at sigma_n = 0 switched shear forces of
// MN/m on and off, a shaken drift gained energy until it blew up, and a static one never settled
// (docs/theory/joint_laws.md).
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
  const bool open = s.elastic_normal <= 0.0;
  const double tau_before = s.tau;
  // Open: the shear is released (its stored energy dissipated) and starts again from zero where
  // the joint closes.
  const double released = open ? s.elastic_shear * s.elastic_shear / (2.0 * p.ks) : 0.0;
  s.elastic_shear = open ? 0.0 : s.elastic_shear + p.ks * k.du_s;
  s.sigma_n = open ? 0.0 : s.elastic_normal;
  s.tau = s.elastic_shear;
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
  r.dissipated = released;
}

}  // namespace rockdem

ROCKDEM_REGISTER_JOINT_LAW(rockdem::LinearElastic,
                           "linear elastic joint with no strength (never slips while closed; opens freely, no tension, "
                           "and opening releases its shear); the reference for what the other laws accumulate",
                           "Goodman, Taylor & Brekke (1968), the joint element's elastic stiffnesses")
