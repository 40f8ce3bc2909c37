#include "framework/lab/element_driver.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "framework/core/error.hpp"
#include "framework/core/units.hpp"

namespace rockdem {

ShearPath ShearPath::cycles(double amplitude, int number, double velocity, bool one_sided) {
  ShearPath p;
  p.kind = Kind::cycles;
  p.amplitude = amplitude;
  p.count = number;
  p.velocity = velocity;
  p.one_sided = one_sided;
  return p;
}

ShearPath ShearPath::sinusoid(double amplitude, double frequency, int cycles) {
  ShearPath p;
  p.kind = Kind::sinusoid;
  p.amplitude = amplitude;
  p.frequency = frequency;
  p.count = cycles;
  return p;
}

ShearPath ShearPath::table(std::vector<double> time_s, std::vector<double> disp_m) {
  if (time_s.size() != disp_m.size() || time_s.empty()) {
    throw InputError("shear path table: needs as many times as displacements, at least one point");
  }
  for (std::size_t i = 1; i < time_s.size(); ++i) {
    if (time_s[i] < time_s[i - 1]) throw InputError("shear path table: time must not decrease");
  }
  ShearPath p;
  p.kind = Kind::table;
  p.time = std::move(time_s);
  p.disp = std::move(disp_m);
  return p;
}

namespace {

// Calls fn(du, dt, t) for every increment of `path` starting from offset u0, t being the time
// since the stage start at the end of the increment, computed from the path (not summed), so
// that segment ends fall exactly on the path's times. No allocation. The path starts where the
// joint is: if that is not the path's first point, a straight move to it comes first.
// The most increments one run may take. Each becomes a row of the record (about 100 bytes with
// its extra columns), so 1e7 is about 1 GB: far above any laboratory path at the default step
// (test 9: thousands), and a tiny step or a huge amplitude is refused before anything allocates.
constexpr double kMaxIncrements = 1e7;

InputError too_many_increments(double n, double max_step) {
  return InputError("the shear path takes " + format_quantity(n, Dimension::dimensionless) + " increments at a step of " +
                    format_quantity(max_step, Dimension::length) + "; valid: at most 1e7 increments in a run: use a larger " +
                    "[element] step or a shorter path (amplitudes, cycles, drive values)");
}

template <class Fn>
void for_each_increment(const ShearPath& path, double u0, double max_step, Fn&& fn) {
  double u = u0;
  double t = 0.0;  // stage time at the start of the current segment
  auto move_to = [&](double target, double duration_or_velocity, bool is_velocity) {
    const double dist = std::abs(target - u);
    const double duration = is_velocity ? (duration_or_velocity > 0.0 ? dist / duration_or_velocity : 0.0)
                                        : duration_or_velocity;
    if (dist == 0.0) {
      if (duration > 0.0) fn(0.0, duration, t + duration);  // a pause
      t += duration;
      return;
    }
    const double nd = std::ceil(dist / max_step * (1.0 - 1e-12));
    if (!(nd <= kMaxIncrements)) throw too_many_increments(nd, max_step);
    const long n = std::max(1L, static_cast<long>(nd));
    const double start = u, t_start = t;
    double prev = start, t_prev = t_start;
    for (long i = 1; i <= n; ++i) {
      const double f = static_cast<double>(i) / static_cast<double>(n);
      const double pos = i == n ? target : start + (target - start) * f;
      const double ti = i == n ? t_start + duration : t_start + duration * f;
      fn(pos - prev, ti - t_prev, ti);
      prev = pos;
      t_prev = ti;
    }
    u = target;
    t = t_start + duration;
  };
  switch (path.kind) {
    case ShearPath::Kind::cycles:
      move_to(0.0, path.velocity, true);
      for (int c = 0; c < path.count; ++c) {
        move_to(path.amplitude, path.velocity, true);
        move_to(0.0, path.velocity, true);
        if (!path.one_sided) {
          move_to(-path.amplitude, path.velocity, true);
          move_to(0.0, path.velocity, true);
        }
      }
      break;
    case ShearPath::Kind::sinusoid: {
      move_to(0.0, 0.0, false);
      const double w = 2.0 * std::numbers::pi * path.frequency;
      const double duration = path.count / path.frequency;
      const double travel = 4.0 * path.amplitude * path.count;  // path length of the sinusoid
      const double nd = std::ceil(travel * (std::numbers::pi / 2) / max_step);
      if (!(nd <= kMaxIncrements)) throw too_many_increments(nd, max_step);
      const long n = std::max(1L, static_cast<long>(nd));
      double prev = 0.0, t_prev = t;
      for (long i = 1; i <= n; ++i) {
        const double ti = t + duration * static_cast<double>(i) / static_cast<double>(n);
        // The last point is exactly back at the mated position (sin of a whole number of periods).
        const double pos = i == n ? 0.0 : path.amplitude * std::sin(w * (ti - t));
        fn(pos - prev, ti - t_prev, ti);
        prev = pos;
        t_prev = ti;
      }
      t += duration;
      break;
    }
    case ShearPath::Kind::table:
      move_to(path.disp.front(), 0.0, false);
      t = path.time.front();
      for (std::size_t j = 1; j < path.disp.size(); ++j) {
        move_to(path.disp[j], path.time[j] - path.time[j - 1], false);
        t = path.time[j];  // exactly the table's time at each point
      }
      break;
  }
}

}  // namespace

ElementDriver::ElementDriver(const JointModel& model, ElementOptions options) : model_(model), opt_(options) {
  if (!(opt_.max_step > 0.0)) throw InputError("element driver: the shear step must be positive");
  if (opt_.output_every < 1) throw InputError("element driver: output_every must be at least 1");
  if (!(opt_.frame_stiffness >= 0.0) || (frame() && !(opt_.frame_mass > 0.0))) {
    throw InputError("element driver: a loading frame needs frame_stiffness > 0 and frame_mass > 0 (the top block's "
                     "mass per unit joint area)");
  }
  reset();
}

void ElementDriver::reset() {
  model_.init(state_);
  r_ = JointResponse{};
  time_ = dissipated_ = u_n_ = u_n_stage_ = cns_sigma0_ = cns_u_n0_ = last_du_n_ = last_slope_ = 0.0;
  u_load_ = v_block_ = 0.0;
  steps_ = unconverged_ = 0;
  halving_failed_ = false;
  skipped_halvings_ = 0;
  max_iter_used_ = 0;
}

long ElementDriver::count_increments(const ShearPath& path) const {
  long n = 0;
  for_each_increment(path, load_point(), opt_.max_step, [&](double, double, double) {
    if (static_cast<double>(++n) > kMaxIncrements) throw too_many_increments(static_cast<double>(n), opt_.max_step);
  });
  return n;
}

void ElementDriver::solve_normal(const ElementStage& stage, double du_s, double dt) {
  const JointModel& m = model_for(stage);
  const bool cns = stage.control == NormalControl::constant_stiffness;
  const double K = cns ? stage.normal_stiffness : 0.0;
  JointKinematics k;
  k.du_s = du_s;
  k.dt = dt;
  k.length = opt_.length;
  auto target = [&](double du_n) {
    return cns ? cns_sigma0_ + K * (u_n_ + du_n - cns_u_n0_) : stage.normal_stress;
  };
  JointStateBlock trial;
  JointResponse rr;
  // g(du_n) = sigma_n(du_n) - target(du_n) decreases with du_n (opening unloads the joint).
  auto residual = [&](double du_n) {
    trial = state_;
    k.du_n = du_n;
    m.update(trial, k, rr);
    return rr.sigma_n - target(du_n);
  };
  const double tol = opt_.tolerance * std::max(std::abs(stage.normal_stress), 1e3);
  // Secant iteration safeguarded by a bracket: g decreases with du_n, so a point with g > 0
  // (too much normal stress) lies left of the root and one with g < 0 right of it. Where g is
  // flat (an open joint carries nothing) the step doubles until the root is bracketed.
  double x = last_du_n_;
  double g = residual(x);
  double best_x = x, best_g = g;
  double lo = -kInf, hi = kInf;  // bracket: g(lo) > 0 > g(hi)
  auto note = [&](double xv, double gv) {
    if (gv > 0.0) lo = std::max(lo, xv);
    if (gv < 0.0) hi = std::min(hi, xv);
    if (std::abs(gv) < std::abs(best_g)) {
      best_x = xv;
      best_g = gv;
    }
  };
  note(x, g);
  int it = 0;
  // The last increment's secant slope is the best first guess of dg/d(du_n) (kn alone misses
  // the dilation coupling); the law's tangent kn otherwise.
  double step = g / (last_slope_ > 0.0 ? last_slope_ : std::max(rr.kn, 1.0) + K);
  while (std::abs(best_g) > tol && it < opt_.max_iterations) {
    ++it;
    double xn = x + step;
    const bool bracketed = std::isfinite(lo) && std::isfinite(hi);
    if (bracketed && !(xn > lo && xn < hi)) xn = 0.5 * (lo + hi);
    const double gn = residual(xn);
    note(xn, gn);
    const double secant = -(gn - g) / (xn - x);
    if (std::isfinite(secant) && secant > 0.0) {
      step = gn / secant;
      last_slope_ = secant;
    } else if (!(std::isfinite(lo) && std::isfinite(hi))) {
      step = 2.0 * (xn - x);  // flat: widen the search in the same direction
    } else {
      step = 0.5 * (lo + hi) - xn;
    }
    x = xn;
    g = gn;
  }
  if (std::abs(best_g) > tol) ++unconverged_;
  max_iter_used_ = std::max(max_iter_used_, it);
  if (k.du_n != best_x) residual(best_x);  // make `trial`/`rr` the accepted solution
  state_ = trial;
  r_ = rr;
  u_n_ += best_x;
  last_du_n_ = best_x;
  time_ += dt;
  dissipated_ += rr.dissipated;
  ++steps_;
}

const JointResponse& ElementDriver::begin_stage(const ElementStage& stage) {
  if (stage.control == NormalControl::constant_stiffness && !(stage.normal_stiffness >= 0.0)) {
    throw InputError("element driver: constant normal stiffness needs normal_stiffness >= 0");
  }
  halving_failed_ = false;
  skipped_halvings_ = 0;
  // Normal loading to the stage's normal stress without shear, under constant normal stress.
  ElementStage load = stage;
  load.control = NormalControl::constant_stress;
  last_du_n_ = last_slope_ = 0.0;
  solve_normal(load, 0.0, 0.0);
  last_du_n_ = last_slope_ = 0.0;
  u_n_stage_ = u_n_;
  cns_sigma0_ = r_.sigma_n;
  cns_u_n0_ = u_n_;
  if (frame()) {  // the frame holds the block where it is: its force balances the shear stress
    u_load_ = r_.u_s + r_.tau / opt_.frame_stiffness;
    v_block_ = 0.0;
  }
  return r_;
}

const JointResponse& ElementDriver::step(const ElementStage& stage, double du_s, double dt) {
  if (frame()) {
    frame_step(stage, du_s, dt);
  } else {
    // After a hopeless increment, halving is tried again every 16th increment (a lift-off stretch
    // that halving can get through is not left at 0 MPa for the rest of the stage).
    const bool split = !halving_failed_ || ++skipped_halvings_ % 16 == 0;
    halving_failed_ = !solve_substepped(stage, du_s, dt, 0, split);
    if (!halving_failed_) skipped_halvings_ = 0;
  }
  return r_;
}

void ElementDriver::restore(const Snapshot& s) {
  state_ = s.state;
  r_ = s.r;
  time_ = s.time;
  dissipated_ = s.dissipated;
  u_n_ = s.u_n;
  last_du_n_ = s.last_du_n;
  last_slope_ = s.last_slope;
  steps_ = s.steps;
  unconverged_ = s.unconverged;
}

// A shear increment after which no normal displacement meets the stage's normal condition (a
// steep dilating joint at low normal stress "lifts off": at the fitting step's 0.05 mm the
// stiff default kn left Continuously-Yielding at 0 MPa on test 14 for the rest of the stage, and
// the fit failed there) is taken again as two halves, and so on down to 1/64 of it; the halves
// see the joint's stiffness and dilation change within the increment, as a finer step would.
// When halving did not make the first half meet the condition, the increment cannot meet it at
// any step (a joint that has lost contact for good at these parameters): its second half is solved
// once, not split again, and the increments after it are halved only every 16th until one
// meets the condition (step(); reset at each stage's start). Without that, such an increment cost 127 normal solves instead of
// one, on every increment of the rest of the path (a Mohr-Coulomb fit with reversible dilation
// on the start of test 14's twin ran for minutes). Returns whether all of it met the condition.
bool ElementDriver::solve_substepped(const ElementStage& stage, double du_s, double dt, int depth, bool may_split) {
  constexpr int kMaxDepth = 6;
  const Snapshot before = snapshot();
  solve_normal(stage, du_s, dt);
  const bool met = unconverged_ == before.unconverged;
  if (met || depth >= kMaxDepth || !may_split) return met;
  restore(before);
  last_du_n_ *= 0.5;
  const bool first = solve_substepped(stage, 0.5 * du_s, 0.5 * dt, depth + 1, true);
  const bool second = solve_substepped(stage, 0.5 * du_s, 0.5 * dt, depth + 1, first);
  return first && second;
}

// The block between the frame spring and the joint over one path increment: the load point moves
// by du_load in dt, in sub-steps h no longer than a tenth of the frame period over 2 pi (the
// block-on-frame oscillation that carries a slip event is resolved). Each sub-step solves, by
// backward Euler, for the block's displacement x:
//   R(x) = m (x/h - v)/h + tau(x) - k_f (u_load - u - x) = 0,
// tau(x) being the joint's response to the shear increment x (with the stage's normal condition).
// R increases with x (inertia and frame grow with it, and a joint's stress does not fall with
// more shear within one step unless it is softening, slowly), so a bracketed secant finds the
// root. dt = 0 (a jump of the load point) is solved statically (m = 0).
void ElementDriver::frame_step(const ElementStage& stage, double du_load, double dt) {
  const double kf = opt_.frame_stiffness, m = opt_.frame_mass;
  const double omega = std::sqrt(kf / m);
  const long n_sub = dt > 0.0 ? std::max(1L, static_cast<long>(std::ceil(dt * omega / 0.1))) : 1L;
  const double h = dt / static_cast<double>(n_sub);
  for (long sub = 0; sub < n_sub; ++sub) {
    u_load_ += du_load / static_cast<double>(n_sub);
    const Snapshot before = snapshot();
    const double u0 = before.r.u_s, v0 = v_block_;
    auto residual = [&](double x) {
      restore(before);
      solve_normal(stage, x, h);
      const double inertia = h > 0.0 ? m * (x / h - v0) / h : 0.0;
      return inertia + r_.tau - kf * (u_load_ - u0 - x);
    };
    const double scale = std::max(std::abs(before.r.tau), std::abs(before.r.sigma_n)) + 1e3;
    const double tol = 1e-8 * scale;  // above the inner normal solve's noise (1e-10 of sigma_n)
    // Stiffness of R for the first secant step: inertia + frame + the joint's elastic stiffness.
    const double k_est = (h > 0.0 ? m / (h * h) : 0.0) + kf + std::max(before.r.ks, model_.initial_ks());
    double x0 = h > 0.0 ? v0 * h : 0.0;
    double r0 = residual(x0);
    double lo = -kInf, hi = kInf;  // R(lo) < 0 < R(hi)
    auto note = [&](double x, double rx) {
      if (rx < 0.0) lo = std::max(lo, x);
      if (rx > 0.0) hi = std::min(hi, x);
    };
    note(x0, r0);
    double x1 = x0 - r0 / k_est;
    double r1 = std::abs(r0) <= tol ? r0 : residual(x1);
    if (std::abs(r0) <= tol) x1 = x0;
    note(x1, r1);
    for (int it = 0; it < 60 && std::abs(r1) > tol; ++it) {
      double x2 = r1 != r0 ? x1 - r1 * (x1 - x0) / (r1 - r0) : x1 - r1 / k_est;
      if (std::isfinite(lo) && std::isfinite(hi) && !(x2 > lo && x2 < hi)) x2 = 0.5 * (lo + hi);
      if (!std::isfinite(x2)) x2 = x1 - r1 / k_est;
      x0 = x1;
      r0 = r1;
      x1 = x2;
      r1 = residual(x1);
      note(x1, r1);
    }
    if (std::abs(r1) > tol) ++unconverged_;
    // The state is that of the last residual evaluation, i.e. at x1.
    v_block_ = h > 0.0 ? x1 / h : 0.0;
  }
}

void ElementDriver::append_row(MeasurementFile& out, int stage) const {
  out.rows.push_back({time_, stage, r_.sigma_n / 1e6, r_.u_s * 1e3, r_.tau / 1e6, (u_n_ - u_n_stage_) * 1e3});
  out.extra.push_back({r_.dilation * 1e3, dissipated_});
}

void ElementDriver::run(const std::vector<ElementStage>& stages, MeasurementFile& out, int first_stage_number) {
  if (out.extra_columns.empty()) out.extra_columns = {"dilation_mm", "dissipated_J_per_m2"};
  long total = 0;
  double increments = 0.0;
  for (const auto& st : stages) {
    const long n = count_increments(st.path);
    increments += static_cast<double>(n);
    total += n / opt_.output_every + 2;
  }
  if (increments > kMaxIncrements) throw too_many_increments(increments, opt_.max_step);
  out.rows.reserve(out.rows.size() + static_cast<std::size_t>(total));
  out.extra.reserve(out.extra.size() + static_cast<std::size_t>(total));
  int number = first_stage_number;
  for (const auto& st : stages) {
    if (st.model && std::string(st.model->law().name()) != model_.law().name()) {
      throw InputError("element driver: a stage's model must use the same law as the specimen (" +
                       std::string(model_.law().name()) + "), not " + st.model->law().name());
    }
    begin_stage(st);
    append_row(out, number);
    const long n = count_increments(st.path);
    const double t0 = time_;
    long i = 0;
    for_each_increment(st.path, load_point(), opt_.max_step, [&](double du, double dt, double t) {
      step(st, du, dt);
      time_ = t0 + t;  // the path's time, free of the rounding of summed increments
      ++i;
      if (i % opt_.output_every == 0 || i == n) append_row(out, number);
    });
    ++number;
  }
}

MeasurementFile ElementDriver::run(const std::vector<ElementStage>& stages) {
  MeasurementFile out;
  run(stages, out, 1);
  return out;
}

}  // namespace rockdem
