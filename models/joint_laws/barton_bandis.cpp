// barton_bandis: the Barton-Bandis joint as the CNWRA report states it (section 3.2):
//   tau = sigma_n tan[JRC_mob log10(JCS/sigma_n) + phi_r]         (3-5, JRC mobilised)
//   delta_p = (Ln/500) (JRCn/Ln)^0.33                             (3-6, Barton & Bandis 1982; m)
//   psi = 0.5 JRC_mob log10(JCS/sigma_n)                          (3-7)
// JRC_mob follows Barton's table (report Figure 3-4; Barton et al. 1985): at delta/delta_p =
// 0, 0.3, 0.6, 1, 2, 4, 10, 100 the ratio JRC_mob/JRC_peak is -phi_r/i, 0, 0.75, 1, 0.85, 0.70,
// 0.50, 0 with i = JRC log10(JCS/sigma_n), linear in between and 0 beyond 100.
// Scale corrections from the laboratory length L0 to the field length Ln (Barton & Bandis 1982):
//   JRCn = JRC0 (Ln/L0)^(-0.02 JRC0),  JCSn = JCS0 (Ln/L0)^(-0.03 JRC0).
// Incremental form: delta is the shear displacement travelled on the strength curve; it advances
// only while the joint is on the curve (|tau| at the mobilised strength), by the excess of the
// elastic trial stress over the strength, (|tau_trial| - tau_mob)/ks. From the mated position the
// curve is followed directly (tau_mob(0) = 0), so delta equals the shear displacement and the
// peak is reached at delta_p; on reversal the joint unloads with ks and the reverse peak is the
// strength where forward shearing stopped, as the report notes.
// The total angle is capped at 70 deg (Barton & Choubey 1977 recommend not exceeding it at low
// stress); i is taken as 0 when sigma_n >= JCS (asperities crushed), and psi >= 0 (the report:
// "psi is always positive"; the negative JRC_mob before 0.3 delta_p only removes friction).
// Optional hyperbolic normal closure (Bandis et al. 1983): sigma_n = Kni V / (1 - V/Vm), with
// Kni and Vm given or from the empirical relations of Bandis et al. (1983) / Barton et al. (1985):
//   aj = JRC0/5 (0.2 sigma_c/JCS0 - 0.1) [mm],  Kni = -7.15 + 1.75 JRC0 + 0.02 JCS0/aj [MPa/mm],
//   Vm = -0.1032 - 0.0074 JRC0 + 1.135 (JCS0/aj)^-0.251 [mm].
#include "models/joint_laws/barton_bandis.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

#include "framework/plugin_api/law_support.hpp"

namespace rockdem {
namespace {
constexpr double kDeg = std::numbers::pi / 180.0;
constexpr double kMaxAngle = 70.0 * kDeg;
constexpr std::array<double, 8> kRatioX{0.0, 0.3, 0.6, 1.0, 2.0, 4.0, 10.0, 100.0};
constexpr std::array<double, 8> kRatioJrc{0.0 /*-phi_r/i, handled apart*/, 0.0, 0.75, 1.0, 0.85, 0.70, 0.50, 0.0};
}  // namespace

std::vector<Param<BartonBandis::Params>> BartonBandis::Params::spec() {
  using P = Params;
  namespace ls = law_support;
  return {
      real("kn", &P::kn, Dimension::stiffness, "joint normal stiffness for linear closure (Table 4-3 jkn)").positive(),
      real("ks", &P::ks, Dimension::stiffness, "joint shear stiffness for unloading and reversal (Table 4-3 jks)")
          .positive(),
      real("jrc", &P::jrc, Dimension::dimensionless, "joint roughness coefficient JRC0 at lab scale (Table 4-3 jrco)")
          .min(0.0)
          .max(20.0),
      real("jcs", &P::jcs, Dimension::stress, "joint wall compressive strength JCS0 at lab scale (Table 4-3 jcs0)")
          .positive(),
      real("residual_friction", &P::residual_friction, Dimension::angle,
           "residual friction angle phi_r, eq. 3-5 (Table 4-3 phir)")
          .min(0.0)
          .max(kMaxAngle),
      real("ucs", &P::ucs, Dimension::stress,
           "intact uniaxial compressive strength sigma_c (Table 4-3 sigmac); only needed to derive the Bandis "
           "closure constants; 0 = not given")
          .non_negative()
          .def(0.0),
      real("lab_length", &P::lab_length, Dimension::length, "laboratory joint length L0 (Table 4-3 lo)").positive(),
      real("field_length", &P::field_length, Dimension::length,
           "field joint length Ln for the scale corrections and eq. 3-6 (Table 4-3 ln); 0 = same as lab_length")
          .non_negative()
          .def(0.0),
      real("critical_shear_disp", &P::critical_shear_disp, Dimension::length,
           "offset |u_s| beyond which dilation stops (as eq. 3-4); inf = never")
          .positive()
          .def(kInf),
      choice("dilation", &P::dilation, ls::dilation_choices(), "monotonic", ls::dilation_doc()),
      choice("normal_closure", &P::normal_closure, {"linear", "bandis"}, "linear",
             "normal behaviour: linear = constant kn; bandis = hyperbola sigma_n = Kni V/(1 - V/Vm) "
             "(Bandis et al. 1983), kn rising with sigma_n up to the maximum closure Vm"),
      real("initial_normal_stiffness", &P::initial_normal_stiffness, Dimension::stiffness,
           "Bandis closure: initial normal stiffness Kni; 0 = from JRC0, JCS0, ucs (Bandis et al. 1983)")
          .non_negative()
          .def(0.0),
      real("max_closure", &P::max_closure, Dimension::length,
           "Bandis closure: maximum closure Vm; 0 = from JRC0, JCS0, ucs (Bandis et al. 1983)")
          .non_negative()
          .def(0.0),
  };
}

BartonBandis::Derived BartonBandis::derive(const Params& p) {
  Derived d{};
  const double ln = p.field_length > 0.0 ? p.field_length : p.lab_length;
  const double ratio = ln / p.lab_length;
  d.jrc_n = p.jrc * std::pow(ratio, -0.02 * p.jrc);
  d.jcs_n = p.jcs * std::pow(ratio, -0.03 * p.jrc);
  d.delta_p = ln / 500.0 * std::pow(std::max(d.jrc_n, 1e-12) / ln, 0.33);  // eq. 3-6, SI (m)
  d.kni = p.initial_normal_stiffness;
  d.vm = p.max_closure;
  if (p.normal_closure == 1 && (d.kni <= 0.0 || d.vm <= 0.0) && p.ucs > 0.0) {
    const double jcs_mpa = p.jcs / 1e6;
    const double aj_mm = p.jrc / 5.0 * (0.2 * p.ucs / p.jcs - 0.1);
    if (aj_mm > 0.0) {
      if (d.kni <= 0.0) d.kni = (-7.15 + 1.75 * p.jrc + 0.02 * jcs_mpa / aj_mm) * 1e9;  // MPa/mm -> Pa/m
      if (d.vm <= 0.0) d.vm = (-0.1032 - 0.0074 * p.jrc + 1.135 * std::pow(jcs_mpa / aj_mm, -0.251)) * 1e-3;
    }
  }
  return d;
}

void BartonBandis::Params::validate() const {
  if (normal_closure != 1) return;
  const Derived d = derive(*this);
  if (d.kni <= 0.0 || d.vm <= 0.0) {
    const std::string derived =
        ucs <= 0.0 ? std::string("ucs (sigma_c) is not given")
                   : "Bandis et al. (1983) give Kni = " + std::to_string(d.kni / 1e9) + " GPa/m, Vm = " +
                         std::to_string(d.vm * 1e3) + " mm here (they need ucs > 0.5 jcs)";
    throw InputError("joint law 'barton_bandis': normal_closure = \"bandis\" needs initial_normal_stiffness > 0 "
                     "and max_closure > 0, given or derived from jrc, jcs and ucs; " + derived +
                     "; give ucs or both constants");
  }
}

double BartonBandis::initial_kn(const Params& p) {
  return p.normal_closure == 1 ? derive(p).kni : p.kn;
}

namespace {
// i = JRCn log10(JCSn/sigma_n) [rad], 0 when sigma_n >= JCS, capped so that i + phi_r <= 70 deg.
double roughness_i(const BartonBandis::Params& p, const BartonBandis::Derived& d, double sigma_n) {
  const double i = sigma_n > 0.0 ? d.jrc_n * std::log10(d.jcs_n / sigma_n) * kDeg : kMaxAngle;
  return std::clamp(i, 0.0, std::max(0.0, kMaxAngle - p.residual_friction));
}
// JRC_mob log10(JCS/sigma_n) from Barton's table, given i.
double mobilised_from_i(const BartonBandis::Params& p, const BartonBandis::Derived& d, double delta, double i) {
  const double x = delta / d.delta_p;
  if (x < kRatioX[1]) return -p.residual_friction * (1.0 - x / kRatioX[1]);  // -phi_r (tau = 0) to 0
  if (x >= kRatioX.back()) return 0.0;
  std::size_t j = 1;
  while (x >= kRatioX[j + 1]) ++j;
  const double t = (x - kRatioX[j]) / (kRatioX[j + 1] - kRatioX[j]);
  return i * (kRatioJrc[j] + t * (kRatioJrc[j + 1] - kRatioJrc[j]));
}
double strength_from_i(const BartonBandis::Params& p, const BartonBandis::Derived& d, double delta, double sigma_n,
                       double i) {
  if (sigma_n <= 0.0) return 0.0;
  const double angle = std::clamp(p.residual_friction + mobilised_from_i(p, d, delta, i), 0.0, kMaxAngle);
  return sigma_n * std::tan(angle);
}
}  // namespace

double BartonBandis::mobilised_roughness(const Params& p, const Derived& d, double delta, double sigma_n) {
  return mobilised_from_i(p, d, delta, roughness_i(p, d, sigma_n));
}

double BartonBandis::strength(const Params& p, const Derived& d, double delta, double sigma_n) {
  return strength_from_i(p, d, delta, sigma_n, roughness_i(p, d, sigma_n));
}

void BartonBandis::init(const Params&, State& s) { s = State{}; }

namespace {
// Normal stress for an elastic closure v (>= 0), and its tangent stiffness: linear, the Bandis
// hyperbola, or the relation of a normal-response effect (which then replaces the law's own).
struct Closure {
  bool hyperbolic;
  double kn;
  law_support::BandisHyperbola bandis;
  const EffectBase* hook;
  double sigma(double v) const {
    if (hook) return hook->normal_stress(v);
    return hyperbolic ? bandis.sigma(v) : kn * v;
  }
  double tangent(double v) const {
    if (hook) return hook->normal_tangent(v);
    return hyperbolic ? bandis.tangent(v) : kn;
  }
};

// The law's parameters with their derived values, for ShearContext::roughness_at.
struct RoughnessView {
  const BartonBandis::Params* p;
  const BartonBandis::Derived* d;
};
}  // namespace

void BartonBandis::update(const Params& p, const Derived& d, State& s, const JointKinematics& k, JointResponse& r,
                          EffectChain& chain) {
  const Closure cl{p.normal_closure == 1, p.kn, {d.kni, d.vm}, chain.normal()};
  const double u_s_before = s.u_s;
  s.u_s += k.du_s;
  s.u_n += k.du_n;
  r.reset();
  r.ks = p.ks;
  // The closure of the contact decreases with opening and increases with dilation under
  // constrained normal displacement; a negative closure is an open gap (no stresses, no tension).
  const double v_tr = s.closure - k.du_n;
  auto finish_open = [&](double closure) {
    s.closure = closure;
    r.kn = cl.tangent(0.0);
    law_support::report_open(s, r);
  };
  if (s.closure < 0.0 && v_tr < 0.0) return finish_open(v_tr);  // open and staying open
  const double sigma_tr = cl.sigma(v_tr);

  const double sign = law_support::dilation_sign(p.dilation, u_s_before, k.du_s, p.critical_shear_disp,
                                                 s.ucs_reached);
  // Eq. 3-7's roughness with the normal stress at the start of the increment (under constant
  // normal stress, the applied one); the strength uses the consistent stress below.
  const double sigma_psi = s.sigma_n > 0.0 ? s.sigma_n : sigma_tr;
  const double m_tr = mobilised_roughness(p, d, s.delta, sigma_psi);
  const double sigma_fx = law_support::effects_sigma(k, sigma_tr);
  const double strength_fx = strength(p, d, s.delta, sigma_fx);
  ShearContext ctx;
  ctx.sigma_n = sigma_fx;
  ctx.u_s = u_s_before;
  ctx.du_s = k.du_s;
  ctx.plastic_slip = s.delta;
  ctx.basic_friction = p.residual_friction;
  ctx.roughness_angle = std::max(0.0, m_tr);  // the negative pre-peak JRC_mob is not an asperity angle
  ctx.strength = strength_fx;
  ctx.dilation_rate = sign * std::tan(0.5 * std::max(0.0, m_tr));  // eq. 3-7
  ctx.toward_origin = u_s_before * k.du_s < 0.0;
  ctx.dt = k.dt;
  ctx.tau = s.tau;
  ctx.shear_stiffness = p.ks;
  const RoughnessView view{&p, &d};
  ctx.roughness_at = [](const void* law, double slip, double sigma_n) {
    const auto& v = *static_cast<const RoughnessView*>(law);
    return std::max(0.0, mobilised_roughness(*v.p, *v.d, slip, sigma_n));
  };
  ctx.law = &view;
  chain.modify(ctx);
  const law_support::StrengthChange effects(strength_fx, ctx);
  const double rate = ctx.dilation_rate;

  const double tau_old = s.tau;
  const double tau_tr = tau_old + p.ks * k.du_s;
  double tau = tau_tr, travel = 0.0, ddil = 0.0, dus_p = 0.0;
  bool slipping = false;
  auto step = [&](double sigma) {
    const double i = roughness_i(p, d, sigma);  // one log10 per evaluation
    const double s_old = effects(strength_from_i(p, d, s.delta, sigma, i), sigma);
    slipping = std::abs(tau_tr) > s_old;
    if (slipping) {
      travel = (std::abs(tau_tr) - s_old) / p.ks;
      const double s_new = effects(strength_from_i(p, d, s.delta + travel, sigma, i), sigma);
      tau = std::copysign(std::min(std::abs(tau_tr), s_new), tau_tr);
    } else {
      travel = 0.0;
      tau = tau_tr;
    }
    dus_p = slipping ? k.du_s - (tau - tau_old) / p.ks : 0.0;
    ddil = rate * travel;
    return cl.sigma(v_tr + ddil);
  };
  // Whether the strength is consistent with the final normal stress (JointResponse::consistent);
  // report() and the open paths below leave it as set here.
  r.consistent = law_support::solve_increment(rate, sigma_tr, s.sigma_n, k.sigma_n_given, step);

  // No tensile strength: open if the closure after the increment's dilation is negative (the
  // shear increment then acted on no contact and is discarded).
  if (v_tr + ddil < 0.0) return finish_open(std::min(v_tr, v_tr + ddil));
  s.delta += travel;
  s.plastic_slip += std::abs(dus_p);
  s.dilation += ddil;
  s.closure = v_tr + ddil;
  s.sigma_n = cl.sigma(s.closure);
  s.tau = tau;
  r.kn = cl.tangent(s.closure);
  law_support::report(s, r);
  r.slipping = slipping;
  r.dissipated = 0.5 * (tau + tau_old) * dus_p;
}

}  // namespace rockdem

ROCKDEM_REGISTER_JOINT_LAW(rockdem::BartonBandis,
                           "Barton-Bandis joint: JRC-JCS strength with JRC mobilisation and wear, scale "
                           "corrections, eq. 3-7 dilation, optional Bandis hyperbolic closure",
                           "CNWRA report eqs. 3-5..3-7; Barton & Choubey (1977); Bandis et al. (1983); "
                           "Barton, Bandis & Bakhtar (1985)")
