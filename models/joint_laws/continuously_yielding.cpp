// continuously_yielding: the Continuously-Yielding joint of Cundall & Hart (1985) and Cundall &
// Lemos (1990), as written in the CNWRA report (section 3.3; the report cites Cundall and Lemos
// 1988 and the Itasca UDEC manual 1992):
//   d tau = F Ks d u_s                                   (3-8)
//   Ks = a_s sigma_n^e_s,  Kn = a_n sigma_n^e_n          (3-9), bounded by [min, max]
//   F = (1 - tau/tau_o) / (1 - r)                        (3-11)
//   tau_o = sigma_n tan(phi_m) sign(d u_s)               (3-13)
//   phi_m = (phi_m0 - phi) exp(-u_s^p / R) + phi         (3-14)
//   d u_s^p = (1 - F) |d u_s|                            (3-15)
//   psi = atan(|tau| / sigma_n) - phi                    (3-16), = phi_m - phi at the bound (3-17)
// r is 0 initially and is set to tau/tau_o (so F = 1: elastic stiffness) whenever the direction
// of shearing reverses, capped at 0.75 against noise near the bound (report, after eq. 3-12).
// Choices where the report is silent, each documented in docs/theory/joint_laws.md:
//  - the power laws use sigma_n in units of `reference_stress` (1 MPa: Table 4-4 is in MPa);
//  - F is capped at 1 (no response stiffer than elastic), so u_s^p never decreases;
//  - psi is clamped at >= 0 and evaluated with the shear stress at the start of the increment;
//  - an increment is split so that Ks |du| <= tau_o (1 - r) / 2 (at most 32 parts): the explicit
//    update cannot then overshoot the bound; a step crossing the bound from below stops on it;
//  - separation sets tau = 0 and r = 0; re-contact keeps u_s^p (wear) and the dilation.
#include "models/joint_laws/continuously_yielding.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "framework/plugin_api/law_support.hpp"

namespace rockdem {

std::vector<Param<ContinuouslyYielding::Params>> ContinuouslyYielding::Params::spec() {
  using P = Params;
  namespace ls = law_support;
  constexpr double kHalfPi = std::numbers::pi / 2;
  return {
      real("kn", &P::kn, Dimension::stiffness,
           "normal stiffness factor a_n: kn = a_n (sigma_n/reference_stress)^kn_exponent (Table 4-4 jkn)")
          .positive(),
      real("kn_min", &P::kn_min, Dimension::stiffness, "minimum normal stiffness (Table 4-4 minjkn)")
          .non_negative()
          .def(0.0),
      real("kn_max", &P::kn_max, Dimension::stiffness, "maximum normal stiffness (Table 4-4 maxjkn)")
          .positive()
          .def(kInf),
      real("kn_exponent", &P::kn_exponent, Dimension::dimensionless, "normal stiffness exponent e_n (Table 4-4 jen)")
          .min(0.0)
          .max(5.0)
          .def(0.0),
      real("ks", &P::ks, Dimension::stiffness,
           "shear stiffness factor a_s: ks = a_s (sigma_n/reference_stress)^ks_exponent, eq. 3-9 (Table 4-4 jks)")
          .positive(),
      real("ks_min", &P::ks_min, Dimension::stiffness, "minimum shear stiffness (Table 4-4 minjks)")
          .non_negative()
          .def(0.0),
      real("ks_max", &P::ks_max, Dimension::stiffness, "maximum shear stiffness (Table 4-4 maxjks)")
          .positive()
          .def(kInf),
      real("ks_exponent", &P::ks_exponent, Dimension::dimensionless, "shear stiffness exponent e_s (Table 4-4 jes)")
          .min(0.0)
          .max(5.0)
          .def(0.0),
      real("reference_stress", &P::reference_stress, Dimension::stress,
           "stress unit of sigma_n in the stiffness power laws (UDEC tables use MPa)")
          .positive()
          .def(1e6),
      real("initial_friction", &P::initial_friction, Dimension::angle,
           "initial friction angle phi_m0, eq. 3-14 (Table 4-4 jif)")
          .min(0.0)
          .max(kHalfPi, true),
      real("friction", &P::friction, Dimension::angle, "basic friction angle phi, eqs. 3-14, 3-16 (Table 4-4 jfric)")
          .min(0.0)
          .max(kHalfPi, true),
      real("roughness", &P::roughness, Dimension::length,
           "roughness parameter R: plastic displacement scale of the decay of phi_m, eq. 3-14 (Table 4-4 jr)")
          .positive(),
      real("critical_shear_disp", &P::critical_shear_disp, Dimension::length,
           "offset |u_s| beyond which dilation stops (as eq. 3-4); inf = never")
          .positive()
          .def(kInf),
      choice("dilation", &P::dilation, ls::dilation_choices(), "monotonic", ls::dilation_doc()),
  };
}

void ContinuouslyYielding::Params::validate() const {
  auto check = [](const char* what, double a_min, double a_max, double e) {
    if (a_min > a_max) {
      throw InputError(std::string("joint law 'continuously_yielding': ") + what + "_min (" +
                       std::to_string(a_min / 1e9) + " GPa/m) is above " + what + "_max (" +
                       std::to_string(a_max / 1e9) + " GPa/m); the minimum must not exceed the maximum");
    }
    if (e > 0.0 && a_min <= 0.0) {
      throw InputError(std::string("joint law 'continuously_yielding': ") + what + "_exponent > 0 needs " + what +
                       "_min > 0, otherwise the stiffness is zero at zero normal stress and an unloaded joint "
                       "cannot be loaded");
    }
  };
  check("kn", kn_min, kn_max, kn_exponent);
  check("ks", ks_min, ks_max, ks_exponent);
}

double ContinuouslyYielding::normal_stiffness(const Params& p, double sigma_n) {
  const double x = std::max(0.0, sigma_n) / p.reference_stress;
  return std::clamp(p.kn * std::pow(x, p.kn_exponent), p.kn_min, p.kn_max);
}

double ContinuouslyYielding::shear_stiffness(const Params& p, double sigma_n) {
  const double x = std::max(0.0, sigma_n) / p.reference_stress;
  return std::clamp(p.ks * std::pow(x, p.ks_exponent), p.ks_min, p.ks_max);
}

double ContinuouslyYielding::phi_m(const Params& p, double u_p) {
  return (p.initial_friction - p.friction) * std::exp(-u_p / p.roughness) + p.friction;  // eq. 3-14
}

void ContinuouslyYielding::init(const Params&, State& s) { s = State{}; }

void ContinuouslyYielding::update(const Params& p, State& s, const JointKinematics& k, JointResponse& r,
                                  EffectChain& chain) {
  const double u_s_before = s.u_s;
  s.u_s += k.du_s;
  s.u_n += k.du_n;
  r.reset();
  // Normal stiffness of this increment from the normal stress at its start (explicit, as UDEC).
  const law_support::NormalRelation nr{chain.normal(), normal_stiffness(p, s.sigma_n)};
  r.kn = nr.tangent(s.gap > 0.0 ? 0.0 : s.sigma_n);
  auto finish_open = [&] {
    s.r = 0.0;
    r.ks = shear_stiffness(p, 0.0);
    law_support::report_open(s, r);
  };
  double sigma_tr = 0.0;
  if (s.gap > 0.0) {
    s.gap += k.du_n;
    if (s.gap > 0.0) return finish_open();
    sigma_tr = nr.stress(-s.gap);
    s.gap = 0.0;
  } else {
    sigma_tr = nr.add(s.sigma_n, -k.du_n);
  }

  const double sign = law_support::dilation_sign(p.dilation, u_s_before, k.du_s, p.critical_shear_disp,
                                                 s.ucs_reached);
  const double phim = phi_m(p, s.plastic_slip);
  // tan(phi_m) at the increment's starting plastic slip serves the strength below, the sub-step
  // count and each sub-step that starts there (the first, and any after purely elastic ones):
  // tan and exp were half of a Continuously-Yielding fit's time when computed each time.
  const double tan_phim = std::tan(phim);
  const double sigma_fx = law_support::effects_sigma(k, sigma_tr);
  const double bound_fx = sigma_fx * tan_phim;
  // Eq. 3-16 with the stresses at the start of the increment (the normal stress the strength
  // and dilation were in balance with; under constant normal stress this is the applied one).
  const double sigma_psi = s.sigma_n > 0.0 ? s.sigma_n : sigma_tr;
  const double psi = sigma_psi > 0.0 ? std::max(0.0, std::atan(std::abs(s.tau) / sigma_psi) - p.friction) : 0.0;
  ShearContext ctx;
  ctx.sigma_n = sigma_fx;
  ctx.u_s = u_s_before;
  ctx.du_s = k.du_s;
  ctx.plastic_slip = s.plastic_slip;
  ctx.basic_friction = p.friction;
  ctx.roughness_angle = phim - p.friction;
  ctx.strength = bound_fx;
  ctx.dilation_rate = sign * std::tan(psi);  // eq. 3-16
  ctx.dilation_follows_stress = true;
  ctx.toward_origin = u_s_before * k.du_s < 0.0;
  ctx.dt = k.dt;
  ctx.tau = s.tau;
  const double sig0 = s.sigma_n > 0.0 ? s.sigma_n : std::max(0.0, sigma_tr);
  const double ks0 = shear_stiffness(p, sig0);
  ctx.shear_stiffness = ks0;
  ctx.roughness_at = [](const void* law, double slip, double) {
    const auto& q = *static_cast<const Params*>(law);
    return phi_m(q, slip) - q.friction;
  };
  ctx.law = &p;
  chain.modify(ctx);
  const law_support::StrengthChange effects(bound_fx, ctx);
  const double rate = ctx.dilation_rate;

  const double dir = k.du_s > 0.0 ? 1.0 : (k.du_s < 0.0 ? -1.0 : 0.0);
  const bool reversal = dir != 0.0 && s.last_dir != 0.0 && dir != s.last_dir;
  const double tau_old = s.tau;
  // Number of parts of the increment, fixed from the stresses at its start so that the result
  // is a continuous function of du_n (the element driver solves for it).
  int n_sub = 1;
  {
    const double b0 = effects(sig0 * tan_phim, sig0);
    const double r0 = reversal ? -0.75 : s.r;  // a reversal starts near -tau_o: (1 - r) ~ 2
    const double limit = 0.5 * b0 * (1.0 - r0);
    const double need = limit > 0.0 ? std::ceil(ks0 * std::abs(k.du_s) / limit) : 1.0;
    n_sub = static_cast<int>(std::clamp(need, 1.0, 32.0));
  }
  double tau = tau_old, up = s.plastic_slip, rr = s.r, ks = 0.0, ddil = 0.0;
  auto step = [&](double sigma) {
    ks = shear_stiffness(p, sigma);
    tau = tau_old;
    up = s.plastic_slip;
    rr = s.r;
    const double bound0 = effects(sigma * tan_phim, sigma);
    if (reversal) rr = bound0 > 0.0 ? std::min(tau / (dir * bound0), 0.75) : 0.0;
    if (dir != 0.0) {
      const double h = k.du_s / n_sub;
      double up_tan = s.plastic_slip, tan_up = tan_phim;  // tan(phi_m(up_tan))
      for (int i = 0; i < n_sub; ++i) {
        if (up != up_tan) {
          up_tan = up;
          tan_up = std::tan(phi_m(p, up));
        }
        const double bound = effects(sigma * tan_up, sigma);
        if (bound <= 0.0) {  // no strength left: the joint slides freely
          tau = 0.0;
          up += std::abs(h);
          continue;
        }
        const double tau_o = dir * bound;  // eq. 3-13
        const double f = std::min(1.0, (1.0 - tau / tau_o) / (1.0 - rr));  // eq. 3-11
        double tau_new = tau + f * ks * h;                                  // eq. 3-8
        if (dir * tau <= bound && dir * tau_new > bound) tau_new = tau_o;
        const double f_eff = (tau_new - tau) / (ks * h);
        up += (1.0 - f_eff) * std::abs(h);  // eq. 3-15
        tau = tau_new;
      }
    }
    ddil = rate * (up - s.plastic_slip);
    return nr.add(sigma_tr, ddil);
  };
  // Whether the strength is consistent with the final normal stress (JointResponse::consistent);
  // report() and the open paths below leave it as set here.
  r.consistent = law_support::solve_increment(rate, sigma_tr, s.sigma_n, k.sigma_n_given, step);

  // No tensile strength: the joint opens if the stress after the increment's dilation is tensile
  // (the shear increment then acted on no contact and is discarded).
  const double sigma_final = nr.add(sigma_tr, ddil);
  if (sigma_final < 0.0) {
    s.gap = -nr.closure(std::min(sigma_tr, sigma_final));
    return finish_open();
  }
  const double dus_p = k.du_s - (tau - tau_old) / ks;
  const double up_before = s.plastic_slip;
  s.plastic_slip = up;
  s.r = rr;
  if (dir != 0.0) s.last_dir = dir;
  s.dilation += ddil;
  s.sigma_n = sigma_final;
  s.tau = tau;
  r.ks = ks;
  if (nr.hook) r.kn = nr.tangent(sigma_final);
  law_support::report(s, r);
  r.slipping = up > up_before;
  r.dissipated = 0.5 * (tau + tau_old) * dus_p;
}

}  // namespace rockdem

ROCKDEM_REGISTER_JOINT_LAW(rockdem::ContinuouslyYielding,
                           "Continuously-yielding joint: progressive damage, bounding strength sigma_n tan(phi_m) "
                           "with phi_m decaying with plastic slip, stress-dependent stiffnesses",
                           "CNWRA report eqs. 3-8..3-17; Cundall & Hart (1985); Cundall & Lemos (1990); "
                           "Itasca UDEC manual (1992)")
