// mohr_coulomb: linear elastic joint with the Mohr-Coulomb strength of the CNWRA report
// ("Evaluation of rock joint models and computer code UDEC against experimental results", CNWRA
// for the US NRC, section 3.1):
//   tau_o = C + sigma_n tan(phi)                                   (3-1)
//   d tau = Ks d u_s^e                                             (3-2)
//   psi = 0 while |tau| < tau_o                                    (3-3)
//   psi = 0 once |u_s| >= u_cs                                     (3-4)
// plus a tensile strength: beyond it the joint opens and both stresses drop to zero (UDEC).
// Dilation increments d = tan(psi) |du_s^p| raise sigma_n by kn*d under constrained normal
// displacement (UDEC convention); the strength is evaluated at the normal stress after dilation
// (law_support::consistent_sigma), so that a constant-normal-stress path gives exactly
// tau = C + sigma_n tan(phi). The sign of psi on reverse shearing is the `dilation` option.
#include "models/joint_laws/mohr_coulomb.hpp"

#include <cmath>
#include <numbers>

#include "framework/plugin_api/law_support.hpp"

namespace rockdem {

std::vector<Param<MohrCoulomb::Params>> MohrCoulomb::Params::spec() {
  using P = Params;
  namespace ls = law_support;
  return {
      real("kn", &P::kn, Dimension::stiffness, "joint normal stiffness (Table 4-2 jkn)").positive(),
      real("ks", &P::ks, Dimension::stiffness, "joint shear stiffness Ks, eq. 3-2 (Table 4-2 jks)").positive(),
      real("friction", &P::friction, Dimension::angle, "friction angle phi, eq. 3-1 (Table 4-2 jfric)")
          .min(0.0)
          .max(std::numbers::pi / 2, true),
      real("cohesion", &P::cohesion, Dimension::stress, "cohesion C, eq. 3-1 (Table 4-2 jcoh)").non_negative().def(0.0),
      real("tension", &P::tension, Dimension::stress,
           "tensile strength; beyond it the joint opens and sigma_n = tau = 0 (UDEC jten)")
          .non_negative()
          .def(0.0),
      real("dilation_angle", &P::dilation_angle, Dimension::angle,
           "dilation angle psi, active only while slipping, eq. 3-3 (Table 4-2 jdil)")
          .min(0.0)
          .max(std::numbers::pi / 2, true)
          .def(0.0),
      real("critical_shear_disp", &P::critical_shear_disp, Dimension::length,
           "critical shear displacement u_cs: psi = 0 once |u_s| >= u_cs, eq. 3-4 (Table 4-2 'z dilation')")
          .positive()
          .def(kInf),
      choice("dilation", &P::dilation, ls::dilation_choices(), "monotonic", ls::dilation_doc()),
      flag("residual_after_failure", &P::residual_after_failure, true,
           "cohesion and tensile strength drop to zero after the first shear or tensile failure"),
  };
}

void MohrCoulomb::init(const Params& p, State& s) {
  s = State{};
  s.cohesion = p.cohesion;
  s.tension = p.tension;
}

MohrCoulomb::Derived MohrCoulomb::derive(const Params& p) {
  return {std::tan(p.friction), std::tan(p.dilation_angle)};
}

void MohrCoulomb::update(const Params& p, const Derived& d, State& s, const JointKinematics& k, JointResponse& r,
                         EffectChain& chain) {
  const double u_s_before = s.u_s;
  s.u_s += k.du_s;
  s.u_n += k.du_n;
  r.reset();
  const law_support::NormalRelation nr{chain.normal(), p.kn};
  r.kn = nr.tangent(s.gap > 0.0 ? 0.0 : s.sigma_n);
  r.ks = p.ks;
  // Normal trial stress; an open joint carries nothing until the surfaces touch again, and then
  // only the overlap past the touching point loads it. Shear history (slip, dilation) is kept.
  double sigma_tr = 0.0;
  if (s.gap > 0.0) {
    s.gap += k.du_n;
    if (s.gap > 0.0) return law_support::report_open(s, r);
    sigma_tr = nr.stress(-s.gap);
    s.gap = 0.0;
  } else {
    sigma_tr = nr.add(s.sigma_n, -k.du_n);
  }

  const double sign = law_support::dilation_sign(p.dilation, u_s_before, k.du_s, p.critical_shear_disp,
                                                 s.ucs_reached);
  const double tan_phi = d.tan_friction;
  const double sigma_fx = law_support::effects_sigma(k, sigma_tr);
  const double strength_fx = std::max(0.0, s.cohesion + sigma_fx * tan_phi);
  ShearContext ctx;
  ctx.sigma_n = sigma_fx;
  ctx.u_s = u_s_before;
  ctx.du_s = k.du_s;
  ctx.plastic_slip = s.plastic_slip;
  ctx.basic_friction = p.friction;
  ctx.roughness_angle = std::abs(u_s_before) < p.critical_shear_disp ? p.dilation_angle : 0.0;  // eq. 3-4
  ctx.strength = strength_fx;
  ctx.dilation_rate = sign * d.tan_dilation;
  ctx.toward_origin = u_s_before * k.du_s < 0.0;
  ctx.dt = k.dt;
  ctx.tau = s.tau;
  ctx.shear_stiffness = p.ks;
  ctx.roughness_at = [](const void* law, double, double) { return static_cast<const Params*>(law)->dilation_angle; };
  ctx.law = &p;
  chain.modify(ctx);
  const law_support::StrengthChange effects(strength_fx, ctx);
  const double rate = ctx.dilation_rate;

  const double tau_old = s.tau;
  const double tau_tr = tau_old + p.ks * k.du_s;
  double tau = tau_tr, dus_p = 0.0, ddil = 0.0;
  bool slipping = false;
  auto step = [&](double sigma) {
    const double strength = effects(s.cohesion + sigma * tan_phi, sigma);
    slipping = std::abs(tau_tr) > strength;
    tau = slipping ? std::copysign(strength, tau_tr) : tau_tr;
    dus_p = slipping ? k.du_s - (tau - tau_old) / p.ks : 0.0;  // plastic part of the increment
    ddil = rate * std::abs(dus_p);            // eq. 3-3: psi acts only on plastic slip
    return nr.add(sigma_tr, ddil);
  };
  // Whether the strength is consistent with the final normal stress (JointResponse::consistent);
  // report() and the open paths below leave it as set here.
  r.consistent = law_support::solve_increment(rate, sigma_tr, s.sigma_n, k.sigma_n_given, step);

  // Tensile failure (report section 3.1) is judged after the increment's dilation, which pushes
  // the surfaces together under constrained normal displacement: sigma_n becomes zero and the
  // joint opens; the shear increment then acted on no contact and is discarded.
  const double sigma_final = nr.add(sigma_tr, ddil);
  if (sigma_final < -s.tension) {
    s.gap = -nr.closure(std::min(sigma_tr, sigma_final));
    if (p.residual_after_failure) s.cohesion = s.tension = 0.0;
    return law_support::report_open(s, r);
  }
  if (slipping && p.residual_after_failure) s.cohesion = s.tension = 0.0;
  s.plastic_slip += std::abs(dus_p);
  s.dilation += ddil;
  s.sigma_n = sigma_final;
  s.tau = tau;
  r.kn = nr.tangent(sigma_final);
  law_support::report(s, r);
  r.slipping = slipping;
  r.dissipated = 0.5 * (tau + tau_old) * dus_p;
}

}  // namespace rockdem

ROCKDEM_REGISTER_JOINT_LAW(rockdem::MohrCoulomb,
                           "Mohr-Coulomb joint: linear elastic, C + sigma_n tan(phi) strength, tensile strength, "
                           "dilation angle while slipping up to a critical shear displacement",
                           "CNWRA report eqs. 3-1..3-4; Itasca UDEC manual (1992), Coulomb slip joint model")
