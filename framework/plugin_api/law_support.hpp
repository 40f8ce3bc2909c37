#pragma once
// Pieces shared by the published joint laws (mohr_coulomb, barton_bandis, continuously_yielding):
// the `dilation` option that decides the sign of the dilation rate on reverse shearing, and the
// fixed-point loop that makes the strength consistent with the normal stress after dilation.
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "framework/plugin_api/joint_law.hpp"

namespace rockdem::law_support {

// The three readings of dilation on reverse shearing that the CNWRA report compares (section 3
// and 5.1): eqs. 3-4/3-7/3-17 as written ("Dilation 1": always dilates), a sign that follows the
// direction of shear relative to the mated position ("Dilation 2": recovers), and what UDEC 1.83
// did for Mohr-Coulomb (recovery only if the critical shear displacement was never reached).
enum DilationOption : int { kMonotonic = 0, kReversible = 1, kUdecLegacy = 2 };
inline std::vector<std::string> dilation_choices() { return {"monotonic", "reversible", "udec_legacy"}; }
inline const char* dilation_doc() {
  return "dilation on reverse shearing: monotonic = as published, dilation keeps increasing whatever the "
         "direction (report's 'Dilation 1'); reversible = sign follows the direction of shear relative to "
         "the mated position, so dilation recovers ('Dilation 2'); udec_legacy = UDEC 1.83 behaviour: "
         "recovers only if the critical shear displacement was never reached, else constant on reverse";
}

// Multiplier in [-1, 1] of the dilation rate for an increment du_s starting at offset u_s from
// the mated position. u_cs is the critical shear displacement of eq. 3-4 (|u_s| >= u_cs: psi =
// 0); `ucs_reached` is the law's persistent flag used by udec_legacy. The increment is split at
// the mated position and at +-u_cs, so that results do not depend on where the steps fall.
inline double dilation_sign(int option, double u_s, double du_s, double u_cs, bool& ucs_reached) {
  if (du_s == 0.0) return 0.0;
  const double a = u_s, b = u_s + du_s;
  // Length of the part of the segment [x0, x1] (|x| non-increasing or non-decreasing) below u_cs.
  auto inside = [u_cs](double x0, double x1) {
    const double lo = std::min(std::abs(x0), std::abs(x1)), hi = std::max(std::abs(x0), std::abs(x1));
    return std::max(0.0, std::min(hi, u_cs) - lo);
  };
  double toward = 0.0, away = 0.0;  // lengths below u_cs moving toward / away from the origin
  if (a * b < 0.0) {
    toward = inside(a, 0.0);
    away = inside(0.0, b);
  } else if (std::abs(b) < std::abs(a)) {
    toward = inside(a, b);
  } else {
    away = inside(a, b);
  }
  const double len = std::abs(du_s);
  switch (option) {
    case kMonotonic:
      return (toward + away) / len;
    case kReversible:
      return (away - toward) / len;
    default: {  // kUdecLegacy
      const bool was_reached = ucs_reached;
      if (std::max(std::abs(a), std::abs(b)) >= u_cs) ucs_reached = true;
      return (away - (was_reached ? 0.0 : toward)) / len;
    }
  }
}

// The normal stress a law hands its effects (ShearContext::sigma_n) and evaluates their change at:
// the one the caller prescribes for the increment's end where it does (the element driver,
// JointKinematics::sigma_n_given), else the trial stress. At the trial stress an effect that acts
// only in contact (sigma_n > 0) switched off where a dilating increment under a stiff kn has a
// tensile trial stress yet ends in contact, and the strength then jumped with the normal
// displacement the driver solves for (test 14's twin: a scan and halving at each such increment).
inline double effects_sigma(const JointKinematics& k, double sigma_trial) {
  return std::isfinite(k.sigma_n_given) ? k.sigma_n_given : sigma_trial;
}

// The change the effects made to the strength a law computed at the trial normal stress, to be
// applied to the strength at another normal stress (the dilation-consistent one): a factor,
// since strengths scale with sigma_n, or an offset where the base strength is zero. Without
// effects the factor is exactly 1 and the offset exactly 0, so results are bit-identical.
// An effect that gives its strength as a function of the normal stress (ShearContext::
// strength_at) is evaluated at the normal stress asked for, between the factors of the effects
// before and after it.
struct StrengthChange {
  double factor = 1.0, offset = 0.0;
  double (*strength_at)(const double*, double, double) = nullptr;
  const double* args = nullptr;
  double before = 1.0, before_offset = 0.0, after = 1.0;
  // Where the effects were modified (NaN: no memo; see operator()).
  double base_modified = std::numeric_limits<double>::quiet_NaN(), sigma_modified = base_modified, strength_modified = 0.0;
  // `base`: the law's own strength at effects_sigma (ctx.sigma_n); `ctx` after the effects' modify (it must
  // outlive this object).
  StrengthChange(double base, const ShearContext& ctx)
      : factor(base > 0.0 ? ctx.strength / base : 1.0), offset(base > 0.0 ? 0.0 : ctx.strength - base) {
    if (!ctx.strength_at) return;
    strength_at = ctx.strength_at;
    args = ctx.strength_args.data();
    before = base > 0.0 ? ctx.strength_handed / base : 1.0;
    before_offset = base > 0.0 ? 0.0 : ctx.strength_handed - base;
    after = ctx.strength_returned > 0.0 ? ctx.strength / ctx.strength_returned : 1.0;
    // (Only where the effect returned a positive strength: otherwise `after` is 1 and an effect
    // after it may have set a strength that the formula below does not give back.)
    if (ctx.strength_returned > 0.0) {
      base_modified = base;
      sigma_modified = ctx.sigma_n;
      strength_modified = std::max(0.0, ctx.strength);
    }
  }
  // The effects' strength for the law's own `strength` at normal stress `sigma`.
  double operator()(double strength, double sigma) const {
    if (!strength_at) return std::max(0.0, strength * factor + offset);
    // Asked at the stress and base strength the effects were modified at (where the element
    // driver prescribes the stress, the laws' first strength of an increment is asked there):
    // their own answer, without solving the effect's strength again (rate_and_state's friction
    // solve, half of such a fit's time).
    if (strength == base_modified && sigma == sigma_modified) return strength_modified;
    const double handed = std::max(0.0, strength * before + before_offset);
    return std::max(0.0, after * strength_at(args, handed, sigma));
  }
};

// Hyperbolic normal closure of Bandis, Lumsden & Barton (1983): sigma_n = Kni v / (1 - v/Vm) for
// a closure v >= 0, with the asymptote at the maximum closure Vm (v is held just below it).
// Shared by barton_bandis's `normal_closure = "bandis"` and the hyperbolic_normal_closure effect.
struct BandisHyperbola {
  double kni, vm;
  double sigma(double v) const {
    const double vv = std::min(v, vm * (1.0 - 1e-9));
    return kni * vv / (1.0 - vv / vm);
  }
  double closure(double sigma_n) const { return sigma_n * vm / (kni * vm + sigma_n); }
  double tangent(double v) const {
    const double q = 1.0 - std::min(v, vm * (1.0 - 1e-9)) / vm;
    return kni / (q * q);
  }
};

// Normal stress-closure relation of a law with an incremental linear stiffness kn, unless an
// effect supplies its own (EffectChain::normal()). Without one, every expression is the law's
// own linear form (kn*(-x) and -(kn*x) are the same double), so results are bit-identical.
struct NormalRelation {
  const EffectBase* hook;
  double kn;
  double stress(double v) const { return hook ? hook->normal_stress(v) : kn * v; }
  double closure(double sigma_n) const { return hook ? hook->normal_closure(sigma_n) : sigma_n / kn; }
  // The normal stress after closing by dv (< 0: opening) from sigma_n.
  double add(double sigma_n, double dv) const {
    return hook ? hook->normal_stress(hook->normal_closure(sigma_n) + dv) : sigma_n + kn * dv;
  }
  double tangent(double sigma_n) const {
    return hook ? hook->normal_tangent(std::max(0.0, hook->normal_closure(sigma_n))) : kn;
  }
};

// The response fields every law reports from its state.
template <class State>
void report(const State& s, JointResponse& r) {
  r.sigma_n = s.sigma_n;
  r.tau = s.tau;
  r.u_s = s.u_s;
  r.u_n = s.u_n;
  r.dilation = s.dilation;
}

// An open joint carries no stress; its offsets and shear history stay.
template <class State>
void report_open(State& s, JointResponse& r) {
  s.sigma_n = 0.0;
  s.tau = 0.0;
  report(s, r);
  r.open = true;
}

// Solves sigma = step(sigma), where `step(sigma)` performs the shear update with the strength
// evaluated at `sigma` and returns the normal stress after its dilation. Why: under a constant
// normal load the element driver finds du_n such that the final normal stress is the target;
// evaluating the strength at the trial stress (before the dilation increment raises it) would
// make the plateau depend on kn and on the step size. Secant iteration on
// h(sigma) = step(sigma) - sigma, which is linear while the joint slips at a constant rate (one
// secant step then solves it, even where plain fixed-point iteration would diverge, i.e. when
// kn tan(psi) tan(phi) > ks). If it fails, the explicit (trial-stress) update is kept.
// `guess` starts the iteration (the normal stress before the increment is a good one: under a
// constant normal load it is the answer); the result does not depend on it beyond the tolerance.
// The tolerance scales with the larger of the trial stress and the current iterate (the first
// probe with the larger of the trial stress and the guess): a strongly dilating increment can
// leave a trial stress of a few Pa beside an answer of MPa, and a tolerance taken from the trial
// stress alone would then lie below the rounding of the answer (the solve would never stop and
// fall back to the trial stress, a jump of MPa). For the same reason a secant lost to rounding
// (two probes whose h differ by nothing) keeps the last slope.
// Contract: when this returns, the last call made was step(returned sigma). No allocation.
// `found` is false where no fixed point was found (none exists, or the secant did not reach
// one in its 40 steps) and the trial stress, not itself one, was kept: the strength
// was then evaluated at a normal stress other than the one the increment ends at (the law reports
// it as JointResponse::consistent, so that a driver solving for a normal stress can reject it).
struct ConsistentStress {
  double sigma;
  bool found;
};
template <class Step>
ConsistentStress consistent_sigma(double sigma_trial, double guess, Step&& step) {
  double s0 = std::isfinite(guess) ? guess : sigma_trial;
  // A point is accepted only where both it and its residual are finite: a relative tolerance
  // would otherwise take an infinite iterate (an effect's normal stress at its closure limit).
  auto accept = [sigma_trial](double s, double h) {
    return std::isfinite(s) && std::isfinite(h) &&
           std::abs(h) <= 1e-12 * (std::max(std::abs(sigma_trial), std::abs(s)) + 1.0);
  };
  double h0 = step(s0) - s0;
  if (accept(s0, h0)) return {s0, true};
  double h1 = h0, s1 = s0;
  if (std::isfinite(h0)) {
    // The first probe is the fixed-point step, at least 1e-9 of the scale so that the secant
    // slope it gives is not rounding.
    const double min_probe = 1e-9 * (std::max(std::abs(sigma_trial), std::abs(s0)) + 1.0);
    s1 = s0 + (std::abs(h0) >= min_probe ? h0 : std::copysign(min_probe, h0));
    h1 = step(s1) - s1;
    double slope = std::numeric_limits<double>::quiet_NaN();
    for (int it = 0; it < 40 && std::isfinite(h1); ++it) {
      if (accept(s1, h1)) return {s1, true};
      const double next = (h1 - h0) / (s1 - s0);
      if (std::isfinite(next) && next != 0.0) {
        slope = next;
      } else if (!std::isfinite(slope)) {
        break;  // no slope yet and none to keep
      }
      const double s2 = s1 - h1 / slope;
      if (!std::isfinite(s2) || s2 == s1) break;
      s0 = s1;
      h0 = h1;
      s1 = s2;
      h1 = step(s1) - s1;
    }
  }
  if (accept(s1, h1)) return {s1, true};
  // The trial stress can itself be the fixed point (an elastic increment past the fold) when
  // the secant failed elsewhere: then the update is consistent.
  const double h_trial = step(sigma_trial) - sigma_trial;
  return {sigma_trial, accept(sigma_trial, h_trial)};
}

// One increment's normal stress for the three laws: the trial stress when the increment does not
// dilate (rate 0), else the consistent one started from the previous normal stress when the joint
// was closed. Where the caller prescribes the final normal stress (JointKinematics::
// sigma_n_given, finite) the strength is evaluated there, once: the caller solves for the normal
// displacement at which the increment ends at that stress, and at its answer the update is
// consistent (the same fixed point consistent_sigma would look for, found from the outside, where
// it is unique even when the law's own solve has two or none). Same contract as consistent_sigma:
// the last call made was step(the answer). Returns whether the answer is consistent (false: the
// explicit update at the trial stress); with a prescribed stress, true: meeting it is the
// caller's check.
template <class Step>
bool solve_increment(double rate, double sigma_trial, double previous_sigma, double sigma_given, Step&& step) {
  if (std::isfinite(sigma_given)) {
    step(sigma_given);
    return true;
  }
  if (rate == 0.0) {
    step(sigma_trial);  // no dilation: the trial stress is final
    return true;
  }
  return consistent_sigma(sigma_trial, previous_sigma > 0.0 ? previous_sigma : sigma_trial, step).found;
}

}  // namespace rockdem::law_support
