// coulomb_slip: linear elastic joint with Coulomb slip, cohesion and tensile strength.
// Stresses are updated incrementally (Cundall & Hart 1985; Itasca UDEC manual, "joint
// area contact - Coulomb slip"): sigma_n -= kn*du_n, tau += ks*du_s, |tau| <= c + sigma_n*tan(phi).
// Cohesion and tension drop to zero once the joint fails in shear or tension (residual), unless
// `residual_after_failure` is false.
#include <cmath>

#include "models/joint_laws/coulomb_slip.hpp"

namespace rockdem {

std::vector<Param<CoulombSlip::Params>> CoulombSlip::Params::spec() {
  using P = Params;
  return {
      real("kn", &P::kn, Dimension::stiffness, "normal stiffness").positive(),
      real("ks", &P::ks, Dimension::stiffness, "shear stiffness").positive(),
      real("friction", &P::friction, Dimension::angle, "friction angle phi").min(0.0).max(M_PI / 2, true),
      real("cohesion", &P::cohesion, Dimension::stress, "cohesion c").non_negative().def(0.0),
      real("tension", &P::tension, Dimension::stress, "tensile strength").non_negative().def(0.0),
      flag("residual_after_failure", &P::residual_after_failure, true,
           "cohesion and tension drop to zero after shear or tensile failure"),
  };
}

void CoulombSlip::init(const Params& p, State& s) {
  s = State{};
  s.cohesion = p.cohesion;
  s.tension = p.tension;
}

void CoulombSlip::update(const Params& p, State& s, const JointKinematics& k, JointResponse& r,
                         EffectChain& chain) {
  const double u_s_before = s.u_s;
  s.u_s += k.du_s;
  s.u_n += k.du_n;
  r = JointResponse{};
  r.kn = p.kn;
  r.ks = p.ks;
  if (s.gap > 0.0) {  // open: stresses are zero until the surfaces touch again
    s.gap += k.du_n;
    if (s.gap > 0.0) {
      s.sigma_n = 0.0;
      s.tau = 0.0;
      r.open = true;
      r.u_s = s.u_s;
      r.u_n = s.u_n;
      r.dilation = s.dilation;
      return;
    }
    s.sigma_n = -p.kn * s.gap;  // re-contact: only the overlap past the touching point loads
    s.gap = 0.0;
  } else {
    s.sigma_n -= p.kn * k.du_n;
  }
  if (s.sigma_n < -s.tension) {  // tensile failure: opens, stresses released
    s.gap = -s.sigma_n / p.kn;
    s.sigma_n = 0.0;
    s.tau = 0.0;
    if (p.residual_after_failure) s.cohesion = s.tension = 0.0;
    r.open = true;
    r.u_s = s.u_s;
    r.u_n = s.u_n;
    r.dilation = s.dilation;
    return;
  }
  ShearContext ctx;
  ctx.sigma_n = s.sigma_n;
  ctx.u_s = u_s_before;
  ctx.du_s = k.du_s;
  ctx.plastic_slip = s.plastic_slip;
  ctx.basic_friction = p.friction;
  ctx.roughness_angle = 0.0;
  ctx.strength = std::max(0.0, s.cohesion + s.sigma_n * std::tan(p.friction));
  ctx.dilation_rate = 0.0;
  ctx.toward_origin = u_s_before * k.du_s < 0.0;
  chain.modify(ctx);

  const double tau_old = s.tau;
  double tau = s.tau + p.ks * k.du_s;
  const double tmax = ctx.strength;
  if (std::abs(tau) > tmax) {
    tau = std::copysign(tmax, tau);
    r.slipping = true;
    if (p.residual_after_failure) s.cohesion = s.tension = 0.0;
  }
  const double dus_p = k.du_s - (tau - tau_old) / p.ks;  // plastic part of the increment
  s.plastic_slip += std::abs(dus_p);
  if (ctx.dilation_rate != 0.0 && dus_p != 0.0) {
    // Dilation under constrained normal displacement raises the normal stress (UDEC convention).
    const double ddil = ctx.dilation_rate * std::abs(dus_p);
    s.dilation += ddil;
    s.sigma_n += p.kn * ddil;
  }
  s.tau = tau;
  r.sigma_n = s.sigma_n;
  r.tau = s.tau;
  r.u_s = s.u_s;
  r.u_n = s.u_n;
  r.dilation = s.dilation;
  r.dissipated = 0.5 * (tau + tau_old) * dus_p;
}

}  // namespace rockdem

ROCKDEM_REGISTER_JOINT_LAW(rockdem::CoulombSlip,
                           "linear elastic joint with Coulomb slip, cohesion and tensile strength",
                           "Cundall & Hart (1985); Itasca UDEC manual, Coulomb slip joint model")
