#include "framework/lab/virtual_lab/shear_box.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "framework/core/error.hpp"
#include "framework/core/root_finding.hpp"
#include "framework/lab/virtual_lab/rough_profile.hpp"

namespace rockdem::vlab {

namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

// A stage's drive as segments between turning points (or table points), each with the largest
// speed it reaches, so that a segment can be cut into equal time steps.
struct Segment {
  double t0, t1;     // stage time [s]
  double max_speed;  // [m/s]
};

class Drive {
 public:
  explicit Drive(const ShearPath& p) : p_(p) {
    switch (p.kind) {
      case ShearPath::Kind::cycles: {
        if (!(p.velocity > 0.0) || !(p.amplitude > 0.0)) {
          throw InputError("virtual lab: a cycles path needs amplitude > 0 and velocity > 0");
        }
        const double leg = p.amplitude / p.velocity;
        const int legs = p.one_sided ? 2 : 4;
        for (int c = 0; c < p.count; ++c)
          for (int l = 0; l < legs; ++l) {
            const double t0 = leg * static_cast<double>(c * legs + l);
            segments_.push_back({t0, t0 + leg, p.velocity});
          }
        break;
      }
      case ShearPath::Kind::sinusoid: {
        if (!(p.frequency > 0.0) || !(p.amplitude > 0.0)) {
          throw InputError("virtual lab: a sinusoid path needs amplitude > 0 and frequency > 0");
        }
        const double quarter = 0.25 / p.frequency;
        const double vmax = 2.0 * 3.141592653589793 * p.frequency * p.amplitude;
        for (int q = 0; q < 4 * p.count; ++q) {
          segments_.push_back({quarter * q, quarter * (q + 1), vmax});
        }
        break;
      }
      case ShearPath::Kind::table: {
        if (std::abs(p.disp.front()) > 1e-9) {
          throw InputError("virtual lab: a drive table must start at zero displacement (the mated position); it starts at " +
                           std::to_string(p.disp.front() * 1e3) + " mm");
        }
        for (std::size_t k = 1; k < p.time.size(); ++k) {
          const double dt = p.time[k] - p.time[k - 1];
          if (dt <= 0.0) continue;
          segments_.push_back({p.time[k - 1] - p.time.front(), p.time[k] - p.time.front(),
                               std::abs(p.disp[k] - p.disp[k - 1]) / dt});
        }
        break;
      }
    }
  }
  const std::vector<Segment>& segments() const { return segments_; }

  // Drive offset from the stage's origin at stage time t (inside a segment).
  double at(double t) const {
    switch (p_.kind) {
      case ShearPath::Kind::cycles: {
        const double leg = p_.amplitude / p_.velocity;
        const int legs = p_.one_sided ? 2 : 4;
        const double cyc = leg * legs;
        double tc = std::fmod(t, cyc);
        if (t >= cyc * p_.count) tc = 0.0;  // the end of the last cycle
        const double phase = tc / leg;      // 0..legs
        if (phase <= 1.0) return p_.amplitude * phase;
        if (phase <= 2.0) return p_.amplitude * (2.0 - phase);
        if (phase <= 3.0) return -p_.amplitude * (phase - 2.0);
        return -p_.amplitude * (4.0 - phase);
      }
      case ShearPath::Kind::sinusoid:
        return p_.amplitude * std::sin(2.0 * 3.141592653589793 * p_.frequency * t);
      case ShearPath::Kind::table: {
        const double ta = t + p_.time.front();
        auto it = std::upper_bound(p_.time.begin(), p_.time.end(), ta);
        if (it == p_.time.begin()) return p_.disp.front();
        if (it == p_.time.end()) return p_.disp.back();
        const std::size_t k = static_cast<std::size_t>(it - p_.time.begin());
        const double f = (ta - p_.time[k - 1]) / (p_.time[k] - p_.time[k - 1]);
        return p_.disp[k - 1] + f * (p_.disp[k] - p_.disp[k - 1]);
      }
    }
    return 0.0;
  }

 private:
  const ShearPath& p_;
  std::vector<Segment> segments_;
};

}  // namespace

Surfaces matched_surfaces(const std::vector<double>& heights, double grid, double top_length) {
  return matched_surfaces(heights, heights, grid, top_length);
}

Surfaces matched_surfaces(const std::vector<double>& heights, const std::vector<double>& upper, double grid,
                          double top_length) {
  if (upper.size() != heights.size()) throw InputError("virtual lab: the two walls must have the same length");
  Surfaces s;
  s.grid = grid;
  s.bottom = heights;
  const double half_bottom = 0.5 * grid * static_cast<double>(heights.size() - 1);
  s.bottom_x0 = -half_bottom;
  const auto n_top = static_cast<std::size_t>(std::llround(top_length / grid)) + 1;
  if (n_top + 2 > heights.size()) throw InputError("virtual lab: the top block must be shorter than the bottom one");
  const std::size_t first = (heights.size() - n_top) / 2;
  s.top.assign(upper.begin() + static_cast<long>(first), upper.begin() + static_cast<long>(first + n_top));
  s.top_x0 = s.bottom_x0 + grid * static_cast<double>(first);
  return s;
}

ShearBox::ShearBox(Surfaces surfaces, BoxParams params, std::uint64_t noise_seed)
    : surf_(std::move(surfaces)), p_(params), noise_(noise_seed) {
  if (!(surf_.grid > 0.0) || surf_.top.size() < 3 || surf_.bottom.size() < surf_.top.size()) {
    throw InputError("virtual lab: surfaces need a grid > 0, at least 3 top nodes and a bottom at least as long");
  }
  const double shift = (surf_.top_x0 - surf_.bottom_x0) / surf_.grid;
  if (std::abs(shift - std::round(shift)) > 1e-6) {
    throw InputError("virtual lab: top and bottom surfaces must share one grid");
  }
  length_ = surf_.grid * static_cast<double>(surf_.top.size());
  rs_state_ = p_.rs_dc / p_.rs_v0;  // steady state at the reference velocity
  h_.resize(surf_.top.size());
  contacts_.reserve(surf_.top.size());
}

double ShearBox::chain_stiffness() const {
  if (p_.frame_stiffness > 0.0) return 1.0 / (1.0 / p_.frame_stiffness + 1.0 / p_.shear_stiffness);
  return p_.shear_stiffness;
}

double ShearBox::bottom_height(double x, std::size_t* j, double* w) const {
  const double f = (x - surf_.bottom_x0) / surf_.grid;
  const double fl = std::floor(f);
  if (fl < 0.0 || fl + 1.0 >= static_cast<double>(surf_.bottom.size())) {
    *j = surf_.bottom.size();
    *w = 0.0;
    return -kInfinity;
  }
  *j = static_cast<std::size_t>(fl);
  *w = f - fl;
  return surf_.bottom[*j] + *w * (surf_.bottom[*j + 1] - surf_.bottom[*j]);
}

// Slopes at nodes by central differences, interpolated between nodes: the facet inclination is
// continuous in the offset, so the resistance has no jumps where contacts cross nodes.
double ShearBox::bottom_slope(double x) const {
  const auto& b = surf_.bottom;
  std::size_t j;
  double w;
  bottom_height(x, &j, &w);
  if (j >= b.size()) return 0.0;
  auto node = [&](std::size_t k) {
    const std::size_t lo = k == 0 ? 0 : k - 1, hi = std::min(k + 1, b.size() - 1);
    return (b[hi] - b[lo]) / (surf_.grid * static_cast<double>(hi - lo));
  };
  return (1.0 - w) * node(j) + w * node(j + 1);
}

double ShearBox::top_slope(std::size_t i) const {
  const auto& t = surf_.top;
  const std::size_t lo = i == 0 ? 0 : i - 1, hi = std::min(i + 1, t.size() - 1);
  return (t[hi] - t[lo]) / (surf_.grid * static_cast<double>(hi - lo));
}

void ShearBox::evaluate(double s) {
  ++evaluations_;
  const std::size_t n = surf_.top.size();
  // Top and bottom share the grid, so every top node sees the bottom at the same fraction w.
  const double f = (surf_.top_x0 + s - surf_.bottom_x0) / surf_.grid;
  const double fl = std::floor(f);
  const double w = f - fl;
  const auto base = static_cast<long>(fl);
  const auto nb = static_cast<long>(surf_.bottom.size());
  double hmax = -kInfinity;
  for (std::size_t i = 0; i < n; ++i) {
    const long j = base + static_cast<long>(i);
    if (j < 0 || j + 1 >= nb) {
      h_[i] = -kInfinity;  // past the end of the bottom block: nothing to touch
      continue;
    }
    const auto ju = static_cast<std::size_t>(j);
    h_[i] = surf_.bottom[ju] + w * (surf_.bottom[ju + 1] - surf_.bottom[ju]) - surf_.top[i];
    hmax = std::max(hmax, h_[i]);
  }
  contacts_.clear();
  if (!(sigma_ > 0.0) || hmax == -kInfinity) {
    lift_ = hmax == -kInfinity ? lift_ : hmax;
    return;
  }
  // Normal equilibrium: sum_i min(max(h_i - v, 0), cap) = target (overlaps, in m): piecewise
  // linear and decreasing in v; Newton from the last lift, safeguarded by bisection.
  const double kc = p_.contact_stiffness;
  const double cap = p_.wall_strength / kc;
  const double target = sigma_ * length_ / (kc * surf_.grid);
  double lo = -kInfinity, hi = hmax;
  double v = std::min(lift_, hmax);
  for (int it = 0; it < 200; ++it) {
    double sum = 0.0;
    long active = 0;
    for (std::size_t i = 0; i < n; ++i) {
      const double d = h_[i] - v;
      if (d > 0.0) {
        if (d < cap) {
          sum += d;
          ++active;
        } else {
          sum += cap;
        }
      }
    }
    const double F = sum - target;
    if (std::abs(F) <= 1e-13 * target) break;
    if (F > 0.0) lo = v; else hi = v;
    if (hi - lo <= 1e-15 * (1.0 + std::abs(v))) break;
    double vn = active > 0 ? v + F / static_cast<double>(active) : v - (F > 0.0 ? -cap : std::max(-F, cap));
    if (!(vn < hi) || !(vn > lo)) vn = lo == -kInfinity ? v - std::max(-F, cap) : 0.5 * (lo + hi);
    v = vn;
  }
  lift_ = v;
  const double x_shift = surf_.top_x0 + s;
  for (std::size_t i = 0; i < n; ++i) {
    const double d = h_[i] - v;
    if (d <= 0.0) continue;
    const double x = x_shift + surf_.grid * static_cast<double>(i);
    const double slope = 0.5 * (bottom_slope(x) + top_slope(i));
    contacts_.push_back({i, std::min(kc * d, p_.wall_strength) * surf_.grid, std::atan(slope), slope, d});
  }
}

double ShearBox::horizontal(double mu_signed, double* d_dmu) const {
  // tan(theta + phi) = (tan theta + mu) / (1 - mu tan theta) while |theta + phi| <= max_angle.
  const double phi = std::atan(mu_signed);
  const double cap = std::tan(p_.max_angle);
  double sum = 0.0, dsum = 0.0;
  for (const auto& c : contacts_) {
    const double beta = c.theta + phi;
    if (beta >= p_.max_angle) {
      sum += c.vertical * cap;
    } else if (beta <= -p_.max_angle) {
      sum -= c.vertical * cap;
    } else {
      const double den = 1.0 - mu_signed * c.tan_theta;
      sum += c.vertical * (c.tan_theta + mu_signed) / den;
      dsum += c.vertical * (1.0 + c.tan_theta * c.tan_theta) / (den * den);
    }
  }
  if (d_dmu) *d_dmu = dsum / length_;
  return sum / length_;
}

void ShearBox::set_normal_stress(double sigma_n) {
  sigma_ = sigma_n;
  evaluate(s_);
}

Resistance ShearBox::resistance(double s) {
  evaluate(s);
  const double mu = std::tan(p_.friction);
  Resistance r;
  r.lift = lift_;
  r.tau_forward = horizontal(mu);
  r.tau_backward = horizontal(-mu);
  r.contact_fraction = static_cast<double>(contacts_.size()) / static_cast<double>(surf_.top.size());
  return r;
}

}  // namespace rockdem::vlab

namespace rockdem::vlab {

// Removes material at a contact: depth_top from the top block's face at its node (the face
// recedes upwards), depth_bottom from the bottom face where that node sits now (shared between
// the two bottom nodes around it by the interpolation weights, so the volume is depth * grid).
void ShearBox::remove(std::size_t i, double depth_top, double depth_bottom) {
  surf_.top[i] += depth_top;
  const double x = surf_.top_x0 + s_ + surf_.grid * static_cast<double>(i);
  std::size_t j;
  double w;
  bottom_height(x, &j, &w);
  if (j + 1 < surf_.bottom.size()) {
    surf_.bottom[j] -= (1.0 - w) * depth_bottom;
    surf_.bottom[j + 1] -= w * depth_bottom;
  }
  worn_volume_ += (depth_top + depth_bottom) * surf_.grid;
}

// Archard (1953) in frictional-work form: volume k_w W_f / p_crush from each surface, where the
// work is done. The contact force leans phi from the facet normal, so with beta = theta + phi
// (capped) the friction force is V sin|phi| / cos(beta) and the facet slip |ds| / cos(theta).
void ShearBox::wear(double ds, double mu_signed) {
  if (!(p_.wear_coefficient > 0.0) || ds == 0.0) return;
  const double phi = std::atan(mu_signed);
  const double sin_phi = std::abs(std::sin(phi));
  const double per_work = p_.wear_coefficient / p_.wall_strength / surf_.grid;
  for (const auto& c : contacts_) {
    const double beta = std::clamp(c.theta + phi, -p_.max_angle, p_.max_angle);
    const double work = c.vertical * sin_phi / std::cos(beta) * std::abs(ds) / std::cos(c.theta);
    const double depth = per_work * work;
    remove(c.node, depth, depth);
  }
}

// Overlap beyond the crushing pressure is removed, half from each surface.
void ShearBox::crush() {
  const double cap = p_.wall_strength / p_.contact_stiffness;
  bool any = false;
  for (const auto& c : contacts_) {
    if (c.overlap > cap) {
      const double e = 0.5 * (c.overlap - cap);
      remove(c.node, e, e);
      any = true;
    }
  }
  if (any) evaluate(s_);
}

// Regularised rate-and-state friction (Rice & Ben-Zion 1996; Lapusta et al. 2000):
//   mu = a asinh( V / (2 V0) exp(Psi / a) ),  Psi = f0 + b ln(V0 theta / Dc),
// which equals Dieterich-Ruina's f0 + a ln(V/V0) + b ln(V0 theta/Dc) away from V = 0 and is odd
// and smooth through it; f0 = tan(friction).
double ShearBox::mu_rate_state(double velocity, double* dmu_dv) const {
  const double psi = std::tan(p_.friction) + p_.rs_b * std::log(p_.rs_v0 * rs_state_ / p_.rs_dc);
  // 1/c = 2 V0 exp(-Psi/a) cannot overflow (c itself can at large Psi/a).
  const double inv_c = 2.0 * p_.rs_v0 * std::exp(-psi / p_.rs_a);
  if (dmu_dv) *dmu_dv = p_.rs_a / std::sqrt(inv_c * inv_c + velocity * velocity);
  return p_.rs_a * std::asinh(velocity / inv_c);
}

void ShearBox::quasi_static_step(double u) {
  ++steps_;
  const double k = chain_stiffness();
  const double mu = std::tan(p_.friction);
  const double trial = k * (u - s_);
  const double rf = horizontal(mu), rb = horizontal(-mu);
  if (trial <= rf && trial >= rb) {
    tau_ = trial;
    return;
  }
  const double d = trial > rf ? 1.0 : -1.0;
  // g > 0: the chain pushes harder than the contact resists in direction d; slide on. March in
  // steps of at most half a grid step (so no asperity is jumped over), then bracket the first
  // point where g <= 0 (regula falsi, Illinois variant).
  double last = s_;  // the point the contacts were last evaluated at
  auto g = [&](double s) {
    evaluate(s);
    last = s;
    return d * (k * (u - s) - horizontal(d * mu));
  };
  const double tol = 1e-10 * std::max(sigma_, 1e3);
  const double s_start = s_;
  double s0 = s_, g0 = d * (trial - (d > 0 ? rf : rb));
  double s1 = s0, g1 = g0;
  double ds = std::min(0.5 * surf_.grid, g0 / k);
  for (long it = 0; it < 10000000; ++it) {
    s1 = s0 + d * ds;
    g1 = g(s1);
    if (g1 <= tol) break;
    // Still pushed on: aim 1.5 times past the secant's root to bracket it in few evaluations.
    const double slope = (g1 - g0) / ds;
    s0 = s1;
    g0 = g1;
    ds = slope < 0.0 ? std::min(0.5 * surf_.grid, -1.5 * g0 / slope) : 0.5 * surf_.grid;
    ds = std::max(ds, 1e-12);
  }
  if (g1 < -tol && std::abs(s1 - s0) > 1e-13) {
    // g(s0) > 0 > g(s1): refine to a point where the contact just holds, -tol <= g <= 0 (the end
    // kept is the one with g <= 0).
    root_finding::Bracket br{s0, g0, s1, g1};
    root_finding::illinois(g, br, 60, 1e-13, 0.0, [tol](double, double gs) { return gs <= 0.0 && gs >= -tol; });
    s1 = br.b;
  }
  if (last != s1) evaluate(s1);
  s_ = s1;
  tau_ = k * (u - s_);
  // Wear removes nanometres per step; the contacts of the next step see the new surfaces.
  wear(s_ - s_start, d * mu);
  crush();
}

void ShearBox::inertial_step(double u, double dt) {
  ++steps_;
  const double k = chain_stiffness();
  const double m_dt = p_.moving_mass / dt;
  const double base = -m_dt * vel_ + k * (s_ - u);
  const double lin = m_dt + k * dt;  // df/dV of the inertia and spring terms
  double v_new = 0.0, mu_used = 0.0;
  if (!p_.rate_state) {
    const double mu = std::tan(p_.friction);
    const double fp = base + horizontal(mu), fm = base + horizontal(-mu);
    if (fp < 0.0) {
      v_new = -fp / lin;
      mu_used = mu;
    } else if (fm > 0.0) {
      v_new = -fm / lin;
      mu_used = -mu;
    }
  } else {
    // f(V) = base + lin V + R(mu(V)) is increasing in V: Newton inside a bracket.
    auto f = [&](double vel, double* df) {
      double dmu_dv = 0.0;
      const double mu = mu_rate_state(vel, &dmu_dv);
      double dr = 0.0;
      const double r = horizontal(mu, &dr);
      if (df) *df = lin + dr * dmu_dv;
      return base + lin * vel + r;
    };
    double lo, hi;
    const double f0 = f(0.0, nullptr);
    if (f0 == 0.0) {
      lo = hi = 0.0;
    } else {
      const double step = std::max(std::abs(vel_), 1e-9);
      double a = 0.0, b = f0 > 0.0 ? -step : step;
      while ((f0 > 0.0) == (f(b, nullptr) > 0.0)) {
        a = b;
        b *= 4.0;
        if (std::abs(b) > 1e3) throw InstabilityError("virtual lab: slip velocity above 1 km/s");
      }
      lo = std::min(a, b);
      hi = std::max(a, b);
    }
    double x = std::clamp(vel_, lo, hi);
    for (int it = 0; it < 100 && hi - lo > 1e-14 * (1.0 + std::abs(x)); ++it) {
      double dfx = 0.0;
      const double fx = f(x, &dfx);
      if (fx > 0.0) hi = x; else lo = x;
      double xn = dfx > 0.0 ? x - fx / dfx : 0.5 * (lo + hi);
      if (!(xn > lo && xn < hi)) xn = 0.5 * (lo + hi);
      if (std::abs(xn - x) <= 1e-12 * (1e-6 + std::abs(x))) {
        x = xn;
        break;
      }
      x = xn;
    }
    v_new = x;
    mu_used = mu_rate_state(v_new, nullptr);
  }
  const double ds = v_new * dt;
  if (p_.rate_state) {
    // Ageing law d(theta)/dt = 1 - |V| theta / Dc (Dieterich 1979), exact for constant V:
    // theta e^-x + dt (1 - e^-x)/x with x = |V| dt / Dc, written without the cancellation of
    // Dc/|V| - (Dc/|V| - theta) e^-x at small V.
    const double x = std::abs(v_new) * dt / p_.rs_dc;
    const double g = x > 1e-12 ? -std::expm1(-x) / x : 1.0;
    rs_state_ = rs_state_ * std::exp(-x) + dt * g;
  }
  s_ += ds;
  vel_ = v_new;
  tau_ = k * (u - s_);
  if (ds != 0.0) {
    evaluate(s_);
    wear(ds, mu_used);
    crush();
  }
}

void ShearBox::run(const std::vector<ElementStage>& stages, MeasurementFile& out, int first_stage_number) {
  if (out.extra_columns.empty()) out.extra_columns = {"drive_disp_mm", "contact_fraction"};
  double t_global = out.rows.empty() ? 0.0 : out.rows.back().time_s;
  int number = first_stage_number;
  for (const auto& st : stages) {
    if (st.control != NormalControl::constant_stress) {
      throw InputError("virtual lab: stage " + std::to_string(number) +
                       " asks for constant normal stiffness; the virtual lab runs constant normal stress only");
    }
    Drive drive(st.path);
    // Normal load applied at the present offset (the previous stage ended near the mated
    // position); releasing it in between unloads the shear chain, so the drive restarts there.
    sigma_ = st.normal_stress;
    vel_ = 0.0;
    evaluate(s_);
    crush();
    const double origin = s_;
    const double lift0 = lift_;
    tau_ = 0.0;
    const double t_stage0 = t_global;
    double t_last_row = -kInfinity;
    double u_drive = 0.0;
    auto record = [&](double t, bool force) {
      if (!force && t - t_last_row < p_.output_interval * (1.0 - 1e-9)) return;
      t_last_row = t;
      MeasurementRow r{};
      r.time_s = t_stage0 + t;
      r.stage = number;
      r.normal_stress_MPa = sigma_ * 1e-6;
      r.shear_disp_mm = (s_ + tau_ / p_.shear_stiffness - origin + p_.noise_shear_disp * noise_.normal()) * 1e3;
      r.shear_stress_MPa = (tau_ + p_.noise_stress * noise_.normal()) * 1e-6;
      r.normal_disp_mm = (lift_ - lift0 + p_.noise_normal_disp * noise_.normal()) * 1e3;
      out.rows.push_back(r);
      out.extra.push_back({u_drive * 1e3,
                           static_cast<double>(contacts_.size()) / static_cast<double>(surf_.top.size())});
    };
    record(0.0, true);
    double t_end = 0.0;
    for (const auto& seg : drive.segments()) {
      const double span = seg.t1 - seg.t0;
      double n = std::ceil(seg.max_speed * span / p_.step - 1e-9);
      if (p_.inertial) n = std::max(n, std::ceil(span / p_.time_step - 1e-9));
      const long steps = std::max(1L, static_cast<long>(n));
      for (long q = 1; q <= steps; ++q) {
        const double t = q == steps ? seg.t1 : seg.t0 + span * static_cast<double>(q) / static_cast<double>(steps);
        u_drive = drive.at(t);
        if (p_.inertial) {
          inertial_step(origin + u_drive, span / static_cast<double>(steps));
        } else {
          quasi_static_step(origin + u_drive);
        }
        record(t, false);
      }
      t_end = seg.t1;
    }
    if (t_last_row < t_end) record(t_end, true);
    t_global = t_stage0 + t_end;
    ++number;
  }
}

}  // namespace rockdem::vlab
