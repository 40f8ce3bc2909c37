#include "framework/mechanics/energy_balance.hpp"

#include <algorithm>
#include <cmath>
#include <iterator>

namespace rockdem {

void EnergyBalance::after_zone_forces(const Model& m, double beta) {
  if (!on_ || beta == 0.0) return;
  f_zone_.resize(m.gp.size());
  for (std::size_t i = 0; i < m.gp.size(); ++i) f_zone_[i] = m.gp[i].f;
}

void EnergyBalance::before_boundary_forces(const Model& m) {
  if (!on_) return;
  const std::size_t n = m.gp.size();
  f_bc_.resize(n);
  v_old_.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    f_bc_[i] = m.gp[i].f;
    v_old_[i] = m.gp[i].v;
  }
  vb_old_.resize(m.blocks.size());
  for (std::size_t b = 0; b < m.blocks.size(); ++b) {
    const Block& B = m.blocks[b];
    vb_old_[b] = Eigen::Vector3d(B.vc.x(), B.vc.y(), B.omega);
  }
}

void EnergyBalance::after_boundary_forces(const Model& m) {
  if (!on_) return;
  for (std::size_t i = 0; i < m.gp.size(); ++i) f_bc_[i] = m.gp[i].f - f_bc_[i];
}

// Elastic energy held by the contacts, sigma_n^2/(2 kn) + tau^2/(2 ks) per unit area times the
// length, with the law's present tangent stiffnesses: exact for linear laws (coulomb_slip,
// mohr_coulomb); for laws whose normal stiffness grows with closure (barton_bandis) it counts
// the energy as if the whole stress had been reached at the present stiffness, which
// underestimates what is stored. Also the energy the laws dissipated in this step's update.
double EnergyBalance::contact_energy(const Model& m, double* slip_increment) {
  double e = 0.0, slip = 0.0;
  for (const Contact& c : m.contacts.items) {
    // A decomposed run counts each contact on the process owning its point (partition.hpp).
    if (c.pretouch_gap > 0.0 || !m.part.owns(m.gp[static_cast<std::size_t>(c.point)].block)) continue;
    // What a law dissipated counts even in the update that opened the joint (linear_elastic
    // releases its stored shear then); an open joint holds no energy.
    slip += c.length * c.response.dissipated;
    if (c.response.open) continue;
    const JointModel& law = *m.contacts.models[static_cast<std::size_t>(c.joint)];
    const double kn = c.response.kn > 0.0 ? c.response.kn : law.initial_kn();
    const double ks = c.response.ks > 0.0 ? c.response.ks : law.initial_ks();
    const double sn = c.response.sigma_n, tau = c.response.tau;
    e += c.length * ((kn > 0.0 ? sn * sn / (2.0 * kn) : 0.0) + (ks > 0.0 ? tau * tau / (2.0 * ks) : 0.0));
  }
  if (slip_increment) *slip_increment = slip;
  return e;
}

void EnergyBalance::refreshed(double before, double after) {
  if (!on_ || !started_) return;
  t_.refresh += after - before;
  t_.contact += after - before;
  scale_ = std::max(scale_, t_.largest());
  t_.error = scale_ > 0.0 ? t_.imbalance() / scale_ : 0.0;
}

void EnergyBalance::after_step(const Model& m, const EnergyMasses& masses, double dt, double beta) {
  if (!on_) return;
  const std::size_t ng = m.gp.size(), nb = m.blocks.size(), nz = m.zones.size();
  // A model whose arrays changed size since the last step (blocks removed by an excavation), or a
  // stage that turns Rayleigh damping on, starts a new reference, like the first step, keeping
  // the sums so far (below).
  const bool resized = started_ && (r_prev_.size() != ng || rb_prev_.size() != nb || sig_prev_.size() != nz ||
                                    f_bc_prev_.size() != ng || (beta != 0.0 && f_zone_prev_.size() != ng));
  const bool first = !started_ || resized;
  if (first) {
    r_prev_.assign(ng, Vec2::Zero());
    f_bc_prev_ = f_bc_;
    rb_prev_.assign(nb, Eigen::Vector3d::Zero());
    sig_prev_.resize(nz);
    eps_prev_.resize(nz);
    for (std::size_t z = 0; z < nz; ++z) {
      sig_prev_[z] = m.zones[z].stress;
      eps_prev_[z] = m.zones[z].strain;
    }
    if (beta != 0.0) f_zone_prev_ = f_zone_;
    dt_prev_ = dt;
  }
  // On the first step only the reference is taken: the trapezoids need the forces of the step
  // before, which were not kept.
  const double w = first ? 0.0 : 1.0;
  double kinetic = 0.0, gravity = 0.0, boundary = 0.0, damping = 0.0, zone_work = 0.0;
  // Sums over what this process owns (all of the model in a serial run).
  for_owned_gridpoints(m, [&](int gi) {
    const auto i = static_cast<std::size_t>(gi);
    const GridPoint& g = m.gp[i];
    const Vec2 dx = v_old_[i] * dt_prev_;  // x(n) - x(n-1)
    boundary += w * 0.5 * (f_bc_prev_[i] + f_bc_[i]).dot(dx);
    f_bc_prev_[i] = f_bc_[i];
    if (beta != 0.0) {
      zone_work += w * 0.5 * (f_zone_prev_[i] + f_zone_[i]).dot(dx);
      f_zone_prev_[i] = f_zone_[i];
    }
    if (m.blocks[g.block].rigid) return;
    kinetic += 0.5 * g.mass * v_old_[i].dot(g.v);
    gravity += w * g.mass * m.gravity.dot(dx);
    // The force the applied ones do not explain: damping on a free component, the reaction of
    // a fixed or prescribed one.
    const Vec2 r = masses.gp[i] * (g.v - v_old_[i]) / dt - g.f;
    for (int d = 0; d < 2; ++d) {
      const double work = w * 0.5 * (r_prev_[i][d] + r[d]) * dx[d];
      if (d == 0 ? g.fixed_x : g.fixed_y) boundary += work;
      else damping -= work;
    }
    r_prev_[i] = r;
  });
  for_owned_blocks(m, [&](int bi) {
    const auto b = static_cast<std::size_t>(bi);
    const Block& B = m.blocks[b];
    if (!B.rigid || B.fixed) return;
    const Eigen::Vector3d vo = vb_old_[b], v(B.vc.x(), B.vc.y(), B.omega);
    const Eigen::Vector3d dx = vo * dt_prev_;
    kinetic += 0.5 * B.mass * vo.head<2>().dot(v.head<2>()) + 0.5 * B.inertia * vo[2] * v[2];
    gravity += w * B.mass * m.gravity.dot(dx.head<2>());
    const Eigen::Vector3d inertial(masses.block[b], masses.block[b], masses.inertia[b]);
    const Eigen::Vector3d applied(B.fc.x(), B.fc.y(), B.moment);
    static constexpr std::uint8_t kBit[3] = {Block::kDriveX, Block::kDriveY, Block::kDriveSpin};
    for (int d = 0; d < 3; ++d) {
      if (inertial[d] <= 0.0) continue;
      const double r = inertial[d] * (v[d] - vo[d]) / dt - applied[d];
      const double work = w * 0.5 * (rb_prev_[b][d] + r) * dx[d];
      if (B.prescribed & kBit[d]) boundary += work;
      else damping -= work;
      rb_prev_[b][d] = r;
    }
  });
  double strain = 0.0;
  for_owned_zones(m, [&](int zi) {
    const auto z = static_cast<std::size_t>(zi);
    const Zone& Z = m.zones[z];
    strain += w * 0.5 * (sig_prev_[z] + Z.stress).dot(Z.strain - eps_prev_[z]) * Z.area;
    sig_prev_[z] = Z.stress;
    eps_prev_[z] = Z.strain;
  });
  // Stiffness-proportional Rayleigh damping acts through the zone forces but not the zone
  // stresses: the zone forces' work that the stresses did not take is what it dissipated. The
  // zone forces do work -W on the gridpoints when the zones take up W.
  if (beta != 0.0) damping += -zone_work - strain;
  double slip = 0.0;
  const double contact = contact_energy(m, &slip);
  if (!started_) {
    t_.kinetic_start = kinetic;
    t_.contact_start = contact;
  } else if (resized) {
    // The energy of what was removed leaves the accounting: the stored terms continue from
    // their values before the change.
    t_.kinetic_start += kinetic - t_.kinetic;
    t_.contact_start += contact - (t_.contact + t_.contact_start);
  }
  t_.kinetic = kinetic;
  t_.contact = contact - t_.contact_start;
  t_.strain += strain;
  t_.gravity_work += gravity;
  t_.boundary_work += boundary;
  t_.damping += damping;
  t_.slip += w * slip;
  scale_ = std::max(scale_, t_.largest());
  t_.error = scale_ > 0.0 ? t_.imbalance() / scale_ : 0.0;
  dt_prev_ = dt;
  started_ = true;
}

namespace {

// The per-item arrays a checkpoint carries (saved_items).
constexpr const char* kItemArrays[] = {"energy.r_prev", "energy.f_bc_prev", "energy.f_zone_prev", "energy.rb_prev", "energy.sig_prev",
                                       "energy.eps_prev"};

template <int N, class V>
void put_owned(std::vector<double>& out, std::size_t i, const V& v) {
  for (int d = 0; d < N; ++d) out[N * i + static_cast<std::size_t>(d)] = v[d];
}

template <int N, class V>
void take(std::vector<V>& to, const std::vector<double>& from) {
  to.resize(from.size() / N);
  for (std::size_t i = 0; i < to.size(); ++i)
    for (int d = 0; d < N; ++d) to[i][d] = from[N * i + static_cast<std::size_t>(d)];
}

}  // namespace

std::map<std::string, std::vector<double>> EnergyBalance::saved_items(const Model& m) const {
  std::map<std::string, std::vector<double>> a;
  if (!on_ || !started_) return a;
  a["energy.dt_prev"] = {dt_prev_};
  const std::size_t ng = m.gp.size(), nb = m.blocks.size(), nz = m.zones.size();
  if (r_prev_.size() != ng || f_bc_prev_.size() != ng || rb_prev_.size() != nb || sig_prev_.size() != nz) return a;
  auto& r = a["energy.r_prev"] = std::vector<double>(2 * ng, 0.0);
  auto& fb = a["energy.f_bc_prev"] = std::vector<double>(2 * ng, 0.0);
  const bool zone = f_zone_prev_.size() == ng;
  std::vector<double> fz(zone ? 2 * ng : 0, 0.0);
  for_owned_gridpoints(m, [&](int gi) {
    const auto i = static_cast<std::size_t>(gi);
    put_owned<2>(r, i, r_prev_[i]);
    put_owned<2>(fb, i, f_bc_prev_[i]);
    if (zone) put_owned<2>(fz, i, f_zone_prev_[i]);
  });
  if (zone) a["energy.f_zone_prev"] = std::move(fz);
  auto& rb = a["energy.rb_prev"] = std::vector<double>(3 * nb, 0.0);
  for_owned_blocks(m, [&](int bi) { put_owned<3>(rb, static_cast<std::size_t>(bi), rb_prev_[static_cast<std::size_t>(bi)]); });
  auto& sg = a["energy.sig_prev"] = std::vector<double>(3 * nz, 0.0);
  auto& ep = a["energy.eps_prev"] = std::vector<double>(3 * nz, 0.0);
  for_owned_zones(m, [&](int zi) {
    const auto z = static_cast<std::size_t>(zi);
    put_owned<3>(sg, z, sig_prev_[z]);
    put_owned<3>(ep, z, eps_prev_[z]);
  });
  return a;
}

bool EnergyBalance::restore(const Model& m, const std::map<std::string, std::vector<double>>& a, const EnergyTerms& terms,
                            double scale) {
  const auto get = [&](const char* name, std::size_t size) -> const std::vector<double>* {
    const auto it = a.find(name);
    return it != a.end() && it->second.size() == size ? &it->second : nullptr;
  };
  const std::size_t ng = m.gp.size(), nb = m.blocks.size(), nz = m.zones.size();
  const auto* r = get("energy.r_prev", 2 * ng);
  const auto* fb = get("energy.f_bc_prev", 2 * ng);
  const auto* rb = get("energy.rb_prev", 3 * nb);
  const auto* sg = get("energy.sig_prev", 3 * nz);
  const auto* ep = get("energy.eps_prev", 3 * nz);
  const auto* fz = get("energy.f_zone_prev", 2 * ng);
  const auto* dt = get("energy.dt_prev", 1);
  // Written right after blocks were removed (an excavation, a stage's scale_off), before a step
  // had made the per-item arrays again: only the terms travel, and the next step starts the arrays
  // afresh (after_step's `resized`), as it did in the run that wrote them.
  const bool none = std::none_of(std::begin(kItemArrays), std::end(kItemArrays), [&](const char* k) { return a.count(k) != 0; });
  if (dt && none) {
    for (auto* v : {&r_prev_, &f_bc_prev_, &f_zone_prev_}) v->clear();
    rb_prev_.clear();
    sig_prev_.clear();
    eps_prev_.clear();
    dt_prev_ = (*dt)[0];
    t_ = terms;
    scale_ = scale;
    on_ = started_ = true;
    return true;
  }
  if (!r || !fb || !rb || !sg || !ep || !dt) return false;
  dt_prev_ = (*dt)[0];
  take<2>(r_prev_, *r);
  take<2>(f_bc_prev_, *fb);
  take<3>(rb_prev_, *rb);
  take<3>(sig_prev_, *sg);
  take<3>(eps_prev_, *ep);
  if (fz) take<2>(f_zone_prev_, *fz);
  else f_zone_prev_.clear();
  t_ = terms;
  scale_ = scale;
  on_ = started_ = true;
  return true;
}

}  // namespace rockdem
