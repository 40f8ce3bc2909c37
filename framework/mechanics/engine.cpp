#include "framework/mechanics/engine.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <sstream>
#include <stdexcept>
#include <tuple>

#include "framework/core/error.hpp"
#include "framework/core/threads.hpp"
#include "framework/mechanics/rigid_chord.hpp"
#include "framework/mechanics/zones.hpp"
#include "framework/plugin_api/rock_material.hpp"

namespace rockdem {

Damping Damping::rayleigh(double xi, double f) {
  Damping d;
  d.kind = Kind::rayleigh;
  const double w = 2.0 * std::numbers::pi * f;
  d.alpha = xi * w;
  d.beta = xi / w;
  return d;
}

Damping Damping::rayleigh_band(double xi, double f1, double f2) {
  Damping d;
  d.kind = Kind::rayleigh;
  const double w1 = 2.0 * std::numbers::pi * f1, w2 = 2.0 * std::numbers::pi * f2;
  d.alpha = 2.0 * xi * w1 * w2 / (w1 + w2);
  d.beta = 2.0 * xi / (w1 + w2);
  return d;
}

Damping Damping::rayleigh_mass(double xi, double f) {
  Damping d;
  d.kind = Kind::rayleigh;
  d.alpha = 2.0 * xi * 2.0 * std::numbers::pi * f;
  return d;
}

Damping Damping::rayleigh_stiffness(double xi, double f) {
  Damping d;
  d.kind = Kind::rayleigh;
  d.beta = 2.0 * xi / (2.0 * std::numbers::pi * f);
  return d;
}

Engine::Engine(Model& m, EngineSettings s, Communication& comm) : m_(m), s_(s), comm_(comm) {}

template <class F>
void Engine::on_all_processes(F&& f) {
  if (comm_.size() == 1) {
    f();
    return;
  }
  std::string message;
  char kind = 0;
  try {
    f();
  } catch (const InputError& e) {
    kind = 'i';
    message = e.what();
  } catch (const InstabilityError& e) {
    kind = 'u';
    message = e.what();
  } catch (const std::exception& e) {
    kind = 'e';
    message = e.what();
  }
  const std::string first = comm_.first_message(kind ? std::string(1, kind) + message : std::string());
  if (first.empty()) return;
  if (first[0] == 'i') throw InputError(first.substr(1));
  if (first[0] == 'u') throw InstabilityError(first.substr(1));
  throw std::runtime_error(first.substr(1));
}

const EnergyTerms& Engine::energy() const {
  if (!energy_.tracking()) energy_.start();
  return comm_.size() == 1 ? energy_.terms() : energy_sum_;
}

void Engine::sum_energy() {
  // Each process holds the terms of what it owns; they add up, every step, and the relative error
  // is taken against the largest magnitude the summed terms have reached, as a serial run does.
  const EnergyTerms& t = energy_.terms();
  double v[] = {t.kinetic, t.strain, t.contact, t.gravity_work, t.boundary_work, t.slip, t.damping, t.kinetic_start, t.contact_start, t.refresh};
  comm_.sum(v, 10);
  energy_sum_ = EnergyTerms{v[0], v[1], v[2], v[3], v[4], v[5], v[6], v[7], v[8]};
  energy_sum_.refresh = v[9];
  const EnergyTerms& e = energy_sum_;
  energy_scale_ = std::max(energy_scale_, e.largest());
  energy_sum_.error = energy_scale_ > 0.0 ? e.imbalance() / energy_scale_ : 0.0;
}

void Engine::add_condition(std::unique_ptr<BoundaryCondition> bc) { bcs_.push_back(std::move(bc)); }

void Engine::begin_stage(const std::string& name, const Damping& d, bool resuming) {
  stage_ = name;
  stage_time_ = 0.0;
  damping_ = d;
  // A new stage's masses (its own mass scaling) take the momentum rule from the last stage's
  // (compute_time_step), which a checkpoint carries, so that a run restarted from one begins the
  // stage as the uninterrupted run did. A run resumed within a stage recomputes the masses the
  // checkpoint's detection found and so changes nothing.
  stage_start_ = !resuming;
  for (auto& g : m_.gp) {
    g.fixed_x = g.fixed_y = false;
  }
  for (auto& b : m_.blocks) {
    b.fixed = false;
    b.prescribed = 0;
  }
  active_.clear();
  for (auto& bc : bcs_)
    if (bc->active_in(name)) {
      active_.push_back(bc.get());
      bc->setup(m_);
    } else {
      bc->deactivated();
    }
  refresh_contacts();
  // A time step forced above the stable one would only blow up a few steps later: refuse it now,
  // with the value that would do.
  if (s_.fixed_dt > critical_dt_ && !resuming) {
    std::ostringstream os;
    os << "[time] fixed_dt = " << s_.fixed_dt << " s is above the stable time step of this model at the start of stage '"
       << name << "', " << critical_dt_ << " s (2 sqrt(m/k) at its stiffest gridpoint or block); give at most "
       << critical_dt_ * s_.dt_safety << " s (dt_safety = " << s_.dt_safety
       << " times the stable step), or leave fixed_dt out for the automatic step";
    throw InputError(os.str());
  }
  // The damping reference starts from the blocks' present motion, so that a stage depends only on
  // the model state it starts from (a run restarted from a stage checkpoint repeats it exactly).
  const std::size_t nb = m_.blocks.size();
  smooth_v_.assign(nb, Vec2::Zero());
  smooth_w_.assign(nb, 0.0);
  std::vector<double> mass(nb, 0.0);
  for (const auto& g : m_.gp)
    if (!m_.blocks[g.block].rigid) {
      smooth_v_[g.block] += g.mass * g.v;
      mass[g.block] += g.mass;
    }
  for (std::size_t b = 0; b < nb; ++b) {
    if (m_.blocks[b].rigid) {
      smooth_v_[b] = m_.blocks[b].vc;
      smooth_w_[b] = m_.blocks[b].omega;
    } else if (mass[b] > 0.0) {
      smooth_v_[b] /= mass[b];
    }
  }
  last_good_.take(m_);
}

void Engine::refresh_contacts(bool account) {
  account = account && energy_.tracking();
  const double before = account ? EnergyBalance::stored_in_contacts(m_) : 0.0;
  on_all_processes([&] {
    // Which blocks each process needs as ghosts after the motion since the last detection (a
    // wider margin than the broad phase's, so that none it would pair is missed), then their
    // present state, then detection on the blocks current here.
    comm_.borders(m_, 2.0 * s_.detection.distance);
    comm_.forward(m_);
    detect_contacts(m_, s_.detection, s_.threads);
  });
  if (account) {
    energy_.refreshed(before, EnergyBalance::stored_in_contacts(m_));
    // The step summed the terms before this refresh; what is sampled after it sees it too.
    if (comm_.size() > 1) sum_energy();
  }
  steps_since_refresh_ = 0;
  travel_since_refresh_ = 0.0;
  compute_time_step();
  // Velocities the mass rule changed reach the other processes' ghosts before the next step's
  // contact forces use them (the same decision on every process: same stage, same points).
  if (momentum_rule_) comm_.forward(m_);
}

OwnerChange Engine::rebalance(double limit) {
  if (!m_.part.decomposed()) return {};
  const auto t0 = std::chrono::steady_clock::now();
  ContactList local;
  OwnerChange ch = comm_.plan_owners(m_, 2.0 * s_.detection.distance, limit, &local);
  if (ch.owner.empty()) {
    if (ch.collected) m_.contacts.restore(std::move(local));  // back to this process's own list
    return ch;
  }
  // The state handed over becomes the last good one: it must be good.
  check_state();
  // What only owners hold, summed over the processes as a checkpoint takes it (each block's
  // contact force, the energy balance's per-item state, the damping's running averages: one
  // process holds each value and the others zero, so each sum is the owner's value exactly). The
  // masses of the time step need not travel: the detection made again below recomputes them, on
  // the new owners, from the same stiffnesses, so they are the same.
  auto held = saved_state();
  held.merge(saved_stage_state());
  if (!ch.collected) comm_.collect(m_, -1);
  assign_owners(m_, std::move(ch.owner), comm_.rank());
  ch.owner = m_.part.owner;
  resume_stage(held, "rebalance");  // the damping's averages (and the same stage clock)
  const std::vector<double>& force = held.at("engine.block_contact_force");
  block_contact_force_.resize(m_.blocks.size());
  for (std::size_t b = 0; b < block_contact_force_.size(); ++b) block_contact_force_[b] = Vec2(force[2 * b], force[2 * b + 1]);
  // The energy balance's terms each process has summed so far stay where they are (only their
  // sum over the processes means anything; restore_state would give them all to process 0).
  // Right after an excavation the balance's arrays are still those of the model before it: it
  // starts them afresh at the next step, wherever the items are, and nothing is handed over.
  if (held.count("energy.r_prev")) {
    const EnergyTerms mine = energy_.terms();
    if (!energy_.restore(m_, held, mine, energy_.scale())) throw std::logic_error("rebalance: the energy balance's state did not fit");
  }
  // The detection made again finds every contact the run's own detection found just before, so
  // it marks none of them as new: which were is put back (a contact field the outputs carry).
  std::vector<ContactKey> fresh;
  for (const Contact& c : m_.contacts.items)
    if (c.fresh) fresh.push_back(c.key);
  std::sort(fresh.begin(), fresh.end());
  refresh_contacts(false);
  for (Contact& c : m_.contacts.items)
    if (std::binary_search(fresh.begin(), fresh.end(), c.key)) c.fresh = true;
  last_good_.take(m_);
  ch.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return ch;
}

void Engine::take_out(const std::function<Renumbering()>& remove) {
  check_state();
  // Each block's values come from its owner (summed as a checkpoint takes them).
  const auto held = saved_stage_state();
  const std::vector<double> force = block_forces();
  if (m_.part.decomposed()) comm_.collect(m_, -1);
  const Renumbering r = remove();
  if (r.block.empty()) {  // nothing to take out after all: the collected state is left by a detection
    if (m_.part.decomposed()) refresh_contacts(false);
    return;
  }
  const std::vector<double>& avg = held.at("engine.damping_averages");
  const std::size_t nb = m_.blocks.size();
  smooth_v_.assign(nb, Vec2::Zero());
  smooth_w_.assign(nb, 0.0);
  block_contact_force_.assign(nb, Vec2::Zero());
  for (std::size_t b = 0; b < r.block.size(); ++b) {
    const int to = r.block[b];
    if (to < 0) continue;
    const auto k = static_cast<std::size_t>(to);
    smooth_v_[k] = Vec2(avg[3 * b], avg[3 * b + 1]);
    smooth_w_[k] = avg[3 * b + 2];
    block_contact_force_[k] = Vec2(force[2 * b], force[2 * b + 1]);
  }
  // The block the last step found least in balance, by its new position (the removed one: none).
  worst_block_ = worst_block_ >= 0 && static_cast<std::size_t>(worst_block_) < r.block.size() && r.block[static_cast<std::size_t>(worst_block_)] >= 0
                     ? r.block[static_cast<std::size_t>(worst_block_)]
                     : 0;
  // The masses the next detection compares with (a mass that grows keeps its point's momentum).
  if (inertial_mass_.size() == r.gp.size()) {
    std::vector<double> mass(m_.gp.size(), 0.0);
    for (std::size_t g = 0; g < r.gp.size(); ++g)
      if (r.gp[g] >= 0) mass[static_cast<std::size_t>(r.gp[g])] = inertial_mass_[g];
    inertial_mass_ = std::move(mass);
  } else {
    inertial_mass_.clear();
  }
  refresh_contacts(false);  // a detection like any other: on the model without the blocks
  last_good_.take(m_);
}

void Engine::compute_time_step() {
  // Stiffness seen by each gridpoint: zones plus contacts (kn*L on the point and, shared by the
  // projection weights, on the edge's two gridpoints).
  for (auto& g : m_.gp) g.stiffness = 0.0;
  zone_stiffness(m_, s_.threads);
  const std::size_t nb = m_.blocks.size();
  std::vector<double> kb(nb, 0.0), krot(nb, 0.0);
  for (const Contact& c : m_.contacts.items) {
    const double k = std::max(c.response.kn, m_.contacts.models[c.joint]->initial_kn());
    const double ks = std::max(c.response.ks, m_.contacts.models[c.joint]->initial_ks());
    // Row sum of the contact spring's stiffness matrix: 2*k*L on the point (its diagonal and the
    // coupling to the edge), shared by the projection weights on the edge's two gridpoints.
    // The contact's span, not its current length, bounds the stiffness it can reach before the next
    // refresh: a contact whose Voronoi cell grows from zero as a block slides must not make the
    // step unstable, and one of zero length must not leave its point without stiffness.
    const double kl = 2.0 * std::max(k, ks) * std::max({c.length, c.span, 1e-12});
    const Block& B = m_.blocks[c.other];
    const int n = static_cast<int>(B.boundary.size());
    m_.gp[c.point].stiffness += kl;
    m_.gp[B.boundary[c.edge]].stiffness += kl * (1.0 - c.s);
    m_.gp[B.boundary[(c.edge + 1) % n]].stiffness += kl * c.s;
  }
  // Rigid blocks: translational and rotational stiffness from their gridpoints.
  for (std::size_t b = 0; b < nb; ++b) {
    const Block& B = m_.blocks[b];
    if (!B.rigid) continue;
    for (int i = B.first_gp; i < B.first_gp + B.n_gp; ++i) {
      kb[b] += m_.gp[i].stiffness;
      krot[b] += m_.gp[i].stiffness * (m_.gp[i].x - B.xc).squaredNorm();
    }
  }
  // Stiffnesses are absolute row sums, so by Gershgorin omega_max^2 <= max k/m and central
  // differences are stable for dt <= 2 sqrt(m/k) (see zone_stiffness); scaled by dt_safety.
  double dt = std::numeric_limits<double>::max();
  const bool scaling = s_.mass_scaling_dt > 0.0;
  const double target = s_.mass_scaling_dt / (2.0 * s_.dt_safety);  // m = k (dt/2)^2 is just stable
  // Stiffness-proportional Rayleigh damping (zones only) makes a gridpoint a damped oscillator,
  // c = beta k, xi = beta w / 2, for which central differences are stable for
  // w dt <= 2 (sqrt(1 + xi^2) - xi) (Belytschko, Liu & Moran 2000, sec. 6.3), that is
  // dt <= sqrt(beta^2 + 4 m/k) - beta, and a step D needs m >= k D (D + 2 beta) / 4. Taking the
  // whole row sum (contacts too, which carry no beta) errs on the safe side.
  const double beta = damping_.kind == Damping::Kind::rayleigh ? damping_.beta : 0.0;

  // Over what this process owns; the smallest step of all processes applies (below).
  // Scaled masses follow the stiffnesses, which change as contacts come and go and zones deform.
  // A mass that grows under a moving gridpoint keeps its momentum, not its velocity: holding the
  // velocity would add kinetic energy every time a vibrating point's stiffness (and so its mass)
  // rises, and a sliver zone chattering against a joint was pumped that way until it turned
  // inside out. A mass that shrinks keeps its velocity (kinetic energy falls). Within a stage,
  // quasi-static stages (local damping) are left alone: their velocities are a device of the
  // relaxation, local damping takes such energy out, and their load paths stay as they were.
  // At a stage's start the rule applies whatever the damping, to gridpoints and rigid blocks (not
  // at the start of a stage that excavates: its model has other points): a rest after an
  // earthquake scales the masses up a hundredfold (mass_scaling_dt ten times the event's step),
  // and the event's last velocities held under them carried a hundred times the model's kinetic
  // energy into the rest (7,500 J/m in the drift study's first rest, where the event left 78),
  // which the relaxation spent in joint slip (306 J/m) and local damping.
  previous_mass_.swap(inertial_mass_);
  const bool stage_start = std::exchange(stage_start_, false);
  const bool same_points = previous_mass_.size() == m_.gp.size() && (stage_start || damping_.kind != Damping::Kind::local);
  momentum_rule_ = same_points;
  inertial_mass_.assign(m_.gp.size(), 0.0);
  physical_mass_ = scaled_mass_ = 0.0;
  for_owned_gridpoints(m_, [&](int i) {
    const GridPoint& g = m_.gp[static_cast<std::size_t>(i)];
    if (m_.blocks[g.block].rigid) return;
    double mass = g.mass;
    // m = k D (D + 2 beta) / 4 = (k t) t + (k t) beta with t = D / 2 (as written, without beta the
    // masses are those of the undamped rule to the last bit).
    if (scaling && g.stiffness > 0.0) mass = std::max(mass, g.stiffness * target * target + g.stiffness * target * beta);
    inertial_mass_[static_cast<std::size_t>(i)] = mass;
    if (same_points) {
      const double before = previous_mass_[static_cast<std::size_t>(i)];
      if (before > 0.0 && mass > before) m_.gp[static_cast<std::size_t>(i)].v *= before / mass;
    }
    physical_mass_ += g.mass;
    scaled_mass_ += mass;
    if (g.stiffness > 0.0) dt = std::min(dt, std::sqrt(beta * beta + 4.0 * mass / g.stiffness) - beta);
  });
  previous_block_mass_.swap(block_mass_);
  previous_block_inertia_.swap(block_inertia_);
  const bool same_blocks = stage_start && previous_block_mass_.size() == nb && previous_block_inertia_.size() == nb;
  momentum_rule_ = momentum_rule_ || same_blocks;
  block_mass_.assign(nb, 0.0);
  block_inertia_.assign(nb, 0.0);
  for_owned_blocks(m_, [&](int bi) {
    const auto b = static_cast<std::size_t>(bi);
    const Block& B = m_.blocks[b];
    if (!B.rigid) return;
    double mass = B.mass, inertia = B.inertia;
    if (scaling) {
      mass = std::max(mass, kb[b] * target * target);
      inertia = std::max(inertia, krot[b] * target * target);
    }
    block_mass_[b] = mass;
    block_inertia_[b] = inertia;
    if (same_blocks && !B.fixed && B.prescribed == 0) {
      Block& M = m_.blocks[b];
      const double m0 = previous_block_mass_[b], i0 = previous_block_inertia_[b];
      const double moved = m0 > 0.0 && mass > m0 ? m0 / mass : 1.0, turned = i0 > 0.0 && inertia > i0 ? i0 / inertia : 1.0;
      // Its gridpoints' velocities (the chords of the last step, which the contacts' first
      // increments take) follow: the translation and the turn scaled alike.
      const Vec2 vc = M.vc;
      M.vc *= moved;
      M.omega *= turned;
      for (int k = B.first_gp; k < B.first_gp + B.n_gp; ++k) {
        Vec2& v = m_.gp[static_cast<std::size_t>(k)].v;
        v = M.vc + turned * (v - vc);
      }
    }
    physical_mass_ += B.mass;
    scaled_mass_ += mass;
    if (B.fixed || B.prescribed == Block::kDriveAll) return;
    if (kb[b] > 0.0) dt = std::min(dt, 2.0 * std::sqrt(mass / kb[b]));
    if (krot[b] > 0.0) dt = std::min(dt, 2.0 * std::sqrt(inertia / krot[b]));
  });
  // Dashpots of viscous boundaries: an explicit damper is stable for dt < 2 m / c.
  dashpot_.assign(m_.gp.size(), 0.0);
  for (auto* bc : active_) bc->add_dashpots(m_, dashpot_);
  for_owned_gridpoints(m_, [&](int gi) {
    const auto i = static_cast<std::size_t>(gi);
    if (dashpot_[i] > 0.0 && !m_.blocks[m_.gp[i].block].rigid) dt = std::min(dt, 2.0 * inertial_mass_[i] / dashpot_[i]);
  });
  for_owned_blocks(m_, [&](int bi) {
    const auto b = static_cast<std::size_t>(bi);
    const Block& B = m_.blocks[b];
    if (!B.rigid || B.fixed || B.prescribed == Block::kDriveAll) return;
    double c = 0.0, crot = 0.0;
    for (int i = B.first_gp; i < B.first_gp + B.n_gp; ++i) {
      c += dashpot_[static_cast<std::size_t>(i)];
      crot += dashpot_[static_cast<std::size_t>(i)] * (m_.gp[static_cast<std::size_t>(i)].x - B.xc).squaredNorm();
    }
    if (c > 0.0) dt = std::min(dt, 2.0 * block_mass_[b] / c);
    if (crot > 0.0 && block_inertia_[b] > 0.0) dt = std::min(dt, 2.0 * block_inertia_[b] / crot);
  });
  dt = comm_.min(dt);
  if (scaling) {
    double masses[2] = {physical_mass_, scaled_mass_};
    comm_.sum(masses, 2);
    physical_mass_ = masses[0];
    scaled_mass_ = masses[1];
  }
  if (dt == std::numeric_limits<double>::max()) dt = 1e-3;  // nothing couples yet: free flight
  critical_dt_ = dt;
  dt *= s_.dt_safety;
  if (s_.fixed_dt > 0.0) dt = s_.fixed_dt;
  if (scaling) dt = std::min(dt, s_.mass_scaling_dt);
  dt_ = dt;
}

void Engine::contact_forces() {
  block_contact_force_.assign(m_.blocks.size(), Vec2::Zero());
  // One contact's joint-law update for this step; false where it does not act yet (not touching).
  auto& states = m_.contacts.states;
  auto update = [&](Contact& c, std::byte* state) -> bool {
    const Block& B = m_.blocks[c.other];
    const int n = static_cast<int>(B.boundary.size());
    const int ga = B.boundary[c.edge], gb = B.boundary[(c.edge + 1) % n];
    const Vec2 vb = (1.0 - c.s) * m_.gp[ga].v + c.s * m_.gp[gb].v;
    const Vec2 vrel = m_.gp[c.point].v - vb;
    const Vec2 t(c.normal.y(), -c.normal.x());
    JointKinematics k;
    k.du_n = vrel.dot(c.normal) * dt_;
    k.du_s = vrel.dot(t) * dt_;
    k.dt = dt_;
    k.length = c.length;
    if (c.pretouch_gap > 0.0) {
      // Not touching yet: geometry decides (the rounded-corner distance), and the law starts at
      // first touch with the penetration found then, so a point that slides in under an edge of
      // the other block picks up the stress the joint carries there.
      const double gap = -c.overlap;
      if (gap > 0.0) {
        c.pretouch_gap = gap;
        c.response.open = true;
        return false;
      }
      k.du_n = gap;
      c.pretouch_gap = 0.0;
    }
    if (c.pending_closure > 0.0) {
      k.du_n -= c.pending_closure;
      c.pending_closure = 0.0;
    }
    m_.contacts.models[c.joint]->update(state, k, c.response);
    c.fresh = false;
    return true;
  };
  // Its force on the gridpoints and the blocks' sums.
  auto add = [&](const Contact& c) {
    const Block& B = m_.blocks[c.other];
    const int n = static_cast<int>(B.boundary.size());
    const int ga = B.boundary[c.edge], gb = B.boundary[(c.edge + 1) % n];
    const Vec2 f = c.force();
    m_.gp[c.point].f += f;
    m_.gp[ga].f -= (1.0 - c.s) * f;
    m_.gp[gb].f -= c.s * f;
    // Counted once, by the process owning the contact's point (a contact between two processes'
    // blocks is computed on both).
    if (m_.part.owns(m_.gp[c.point].block)) applied_sum_ += 2.0 * f.norm();
    block_contact_force_[m_.gp[c.point].block] += f;
    block_contact_force_[c.other] -= f;
  };
  auto& items = m_.contacts.items;
  if (s_.threads <= 1) {
    for (std::size_t i = 0; i < items.size(); ++i)
      if (update(items[i], states.at(i))) add(items[i]);
    return;
  }
  // The joint laws on several threads (each contact's state is its own); then the forces added
  // in contact order on this thread, as the loop above adds them.
  acting_.resize(items.size());
  threaded_for(s_.threads, 0, static_cast<std::ptrdiff_t>(items.size()),
               [&](std::ptrdiff_t i) {
                 const auto u = static_cast<std::size_t>(i);
                 acting_[u] = update(items[u], states.at(u));
               });
  for (std::size_t i = 0; i < items.size(); ++i)
    if (acting_[i]) add(items[i]);
}

std::vector<double> Engine::block_forces() const {
  std::vector<double> force(2 * m_.blocks.size(), 0.0);
  for (std::size_t b = 0; b < m_.blocks.size() && b < block_contact_force_.size(); ++b)
    if (m_.part.owns(static_cast<int>(b))) {
      force[2 * b] = block_contact_force_[b].x();
      force[2 * b + 1] = block_contact_force_[b].y();
    }
  // One process holds each block's value and the others zero, so the sum is that value exactly.
  if (comm_.size() > 1) comm_.sum_held(force.data(), static_cast<int>(force.size()));
  return force;
}

std::map<std::string, std::vector<double>> Engine::saved_state() const {
  std::map<std::string, std::vector<double>> a{
      {"engine.block_contact_force", block_forces()},
      {"engine.step_values", {ratio_, block_ratio_, static_cast<double>(worst_block_), max_speed_}}};
  // The inertial masses of the last detection, which the next stage's first masses are compared
  // with (the momentum rule): each process's own, zeros elsewhere, so that they add up.
  if (inertial_mass_.size() == m_.gp.size() && block_mass_.size() == m_.blocks.size() &&
      block_inertia_.size() == m_.blocks.size()) {
    std::vector<double> gm(m_.gp.size(), 0.0), bm(2 * m_.blocks.size(), 0.0);
    for_owned_gridpoints(m_, [&](int i) { gm[static_cast<std::size_t>(i)] = inertial_mass_[static_cast<std::size_t>(i)]; });
    for_owned_blocks(m_, [&](int b) {
      const auto k = static_cast<std::size_t>(b);
      bm[2 * k] = block_mass_[k];
      bm[2 * k + 1] = block_inertia_[k];
    });
    if (comm_.size() > 1) {
      comm_.sum_held(gm.data(), static_cast<int>(gm.size()));
      comm_.sum_held(bm.data(), static_cast<int>(bm.size()));
    }
    a["engine.inertial_mass"] = std::move(gm);
    a["engine.block_masses"] = std::move(bm);
  }
  // The energy balance, when something tracks it, goes on from its terms (the whole model's).
  auto items = energy_.saved_items(m_);
  if (comm_.size() > 1) {
    // Per-item arrays add up to the whole model's (each process fills its own items, zeros
    // elsewhere); the last step's dt is the same on every process and is not summed. Tracking
    // starts at the same step everywhere, so every process holds the same keys.
    for (auto& [name, v] : items)
      if (name != "energy.dt_prev") comm_.sum_held(v.data(), static_cast<int>(v.size()));
  }
  if (!items.empty()) {
    const EnergyTerms& t = comm_.size() == 1 ? energy_.terms() : energy_sum_;
    items["energy.terms"] = {t.kinetic, t.strain,        t.contact,       t.gravity_work, t.boundary_work, t.slip,
                             t.damping, t.kinetic_start, t.contact_start, t.error,        t.refresh};
    items["energy.scale"] = {comm_.size() == 1 ? energy_.scale() : energy_scale_};
    a.merge(items);
  }
  return a;
}

void Engine::restore_state(const std::map<std::string, std::vector<double>>& a, const std::string& file) {
  const auto f = a.find("engine.block_contact_force");
  const auto v = a.find("engine.step_values");
  if (f == a.end() || v == a.end()) return;
  if (f->second.size() != 2 * m_.blocks.size() || v->second.size() != 4)
    throw InputError(file + ": the engine state it holds is for " + std::to_string(f->second.size() / 2) +
                     " blocks, the model has " + std::to_string(m_.blocks.size()));
  block_contact_force_.resize(m_.blocks.size());
  for (std::size_t b = 0; b < m_.blocks.size(); ++b) block_contact_force_[b] = Vec2(f->second[2 * b], f->second[2 * b + 1]);
  ratio_ = v->second[0];
  block_ratio_ = v->second[1];
  worst_block_ = static_cast<int>(v->second[2]);
  max_speed_ = v->second[3];
  // Checkpoints from before 2026-12-01 hold no masses: the next stage then starts with none to
  // compare with, and no momentum rule, as runs did before.
  const auto gm = a.find("engine.inertial_mass");
  const auto bm = a.find("engine.block_masses");
  if (gm != a.end() && bm != a.end() && gm->second.size() == m_.gp.size() && bm->second.size() == 2 * m_.blocks.size()) {
    inertial_mass_ = gm->second;
    block_mass_.resize(m_.blocks.size());
    block_inertia_.resize(m_.blocks.size());
    for (std::size_t b = 0; b < m_.blocks.size(); ++b) {
      block_mass_[b] = bm->second[2 * b];
      block_inertia_[b] = bm->second[2 * b + 1];
    }
  }
  const auto t = a.find("energy.terms");
  const auto sc = a.find("energy.scale");
  // Ten terms, and the refresh's change as an eleventh since 2026-11-30 (a checkpoint from before
  // starts it at zero).
  if (t == a.end() || sc == a.end() || (t->second.size() != 10 && t->second.size() != 11) || sc->second.size() != 1) return;
  const auto& x = t->second;
  EnergyTerms whole{x[0], x[1], x[2], x[3], x[4], x[5], x[6], x[7], x[8], x[9]};
  if (x.size() == 11) whole.refresh = x[10];
  // The terms are sums over the processes: one process carries the whole model's so far.
  const EnergyTerms mine = comm_.root() ? whole : EnergyTerms{};
  if (!energy_.restore(m_, a, mine, sc->second[0]))
    throw InputError(file + ": its energy-balance state does not fit the model (" + std::to_string(m_.gp.size()) + " gridpoints, " +
                     std::to_string(m_.zones.size()) + " zones)");
  energy_sum_ = whole;
  energy_scale_ = sc->second[0];
}

std::map<std::string, std::vector<double>> Engine::saved_stage_state() const {
  const std::size_t nb = m_.blocks.size();
  std::vector<double> v(3 * nb, 0.0);
  for (std::size_t b = 0; b < nb && b < smooth_v_.size(); ++b)
    if (m_.part.owns(static_cast<int>(b))) {
      v[3 * b] = smooth_v_[b].x();
      v[3 * b + 1] = smooth_v_[b].y();
      v[3 * b + 2] = smooth_w_[b];
    }
  // One process holds each block's values and the others zero: the sum is the owner's, exactly.
  if (comm_.size() > 1) comm_.sum_held(v.data(), static_cast<int>(v.size()));
  return {{"engine.stage_clock", {stage_time_}}, {"engine.damping_averages", std::move(v)}};
}

void Engine::resume_stage(const std::map<std::string, std::vector<double>>& a, const std::string& file) {
  const auto clock = a.find("engine.stage_clock");
  const auto avg = a.find("engine.damping_averages");
  if (clock == a.end() || avg == a.end() || clock->second.size() != 1)
    throw InputError(file + ": it holds no stage clock (not a checkpoint written within a stage)");
  const std::size_t nb = m_.blocks.size();
  if (avg->second.size() != 3 * nb)
    throw InputError(file + ": its damping state is for " + std::to_string(avg->second.size() / 3) + " blocks, the model has " +
                     std::to_string(nb));
  stage_time_ = clock->second[0];
  smooth_v_.resize(nb);
  smooth_w_.resize(nb);
  for (std::size_t b = 0; b < nb; ++b) {
    smooth_v_[b] = Vec2(avg->second[3 * b], avg->second[3 * b + 1]);
    smooth_w_[b] = avg->second[3 * b + 2];
  }
}

Vec2 Engine::contact_force_on(int block) const {
  return block < static_cast<int>(block_contact_force_.size()) ? block_contact_force_[block] : Vec2::Zero();
}

void Engine::step() {
  const double beta = damping_.kind == Damping::Kind::rayleigh ? damping_.beta : 0.0;
  // The force phase. In a decomposed run an error here (an inverted zone, say) is kept until all
  // processes have exchanged the step's sums, which say whether any of them has one.
  char error_kind = 0;
  std::string error;
  auto forces = [&] {
    update_contact_geometry(m_, s_.threads);
    for_owned_gridpoints(m_, [&](int i) { m_.gp[static_cast<std::size_t>(i)].f.setZero(); });
    for (int b : m_.part.ghost_blocks) {  // contacts put forces on them too; they are not used
      const Block& B = m_.blocks[static_cast<std::size_t>(b)];
      for (int i = B.first_gp; i < B.first_gp + B.n_gp; ++i) m_.gp[static_cast<std::size_t>(i)].f.setZero();
    }
    applied_sum_ = 0.0;
    zone_forces(m_, dt_, beta, s_.threads);
    energy_.after_zone_forces(m_, beta);
    contact_forces();
    energy_.before_boundary_forces(m_);
    for (auto* bc : active_) applied_sum_ += bc->forces(m_, stage_time_);
    energy_.after_boundary_forces(m_);
    // Gravity on the physical (unscaled) mass.
    if (m_.gravity.squaredNorm() > 0.0) {
      for_owned_gridpoints(m_, [&](int i) {
        GridPoint& g = m_.gp[static_cast<std::size_t>(i)];
        if (!m_.blocks[g.block].rigid) {
          g.f += g.mass * m_.gravity;
          applied_sum_ += g.mass * m_.gravity.norm();
        }
      });
    }
    integrate();
  };
  if (comm_.size() == 1) {
    forces();
  } else {
    try {
      forces();
    } catch (const InputError& e) {
      error_kind = 'i';
      error = e.what();
    } catch (const InstabilityError& e) {
      error_kind = 'u';
      error = e.what();
    } catch (const std::exception& e) {
      error_kind = 'e';
      error = e.what();
    }
  }
  // One exchange gives every process the step's global quantities: the unbalanced-force ratio
  // (its sums added in process order), the worst block and whether any process failed.
  const double mine[5] = {unbalanced_, applied_sum_, block_ratio_, static_cast<double>(worst_block_), error_kind ? 1.0 : 0.0};
  comm_.gather_all(mine, 5, step_sums_);
  double unbalanced = 0.0, applied = 0.0;
  bool failed = false;
  for (std::size_t r = 0; r < step_sums_.size(); r += 5) {
    unbalanced += step_sums_[r];
    applied += step_sums_[r + 1];
    if (step_sums_[r + 2] > block_ratio_ || (step_sums_[r + 2] == block_ratio_ && step_sums_[r + 3] < worst_block_)) {
      block_ratio_ = step_sums_[r + 2];
      worst_block_ = static_cast<int>(step_sums_[r + 3]);
    }
    failed = failed || step_sums_[r + 4] != 0.0;
  }
  if (failed) {
    on_all_processes([&] {
      if (error_kind == 'i') throw InputError(error);
      if (error_kind == 'u') throw InstabilityError(error);
      if (error_kind) throw std::runtime_error(error);
    });
  }
  applied_sum_ = applied;
  ratio_ = applied_sum_ > 0.0 ? unbalanced / applied_sum_ : 0.0;
  // A NaN or inf anywhere in the forces (a time function's sqrt(-1), an overflowing stiffness)
  // shows in these sums, which are formed anyway: a free check every step.
  nonfinite_ = !std::isfinite(unbalanced) || !std::isfinite(applied_sum_);
  for (auto* bc : active_) bc->velocities(m_, stage_time_ + dt_);
  for (auto* bc : active_) bc->end_step(m_, dt_);
  // Positions from the final half-step velocities (prescribed ones included).
  // (The largest speed is the same whichever thread finds it.)
  double speed2 = 0.0;
  moved_dt_ = dt_;
  auto move_gridpoint = [&](std::ptrdiff_t i) {
    GridPoint& g = m_.gp[static_cast<std::size_t>(i)];
    if (m_.blocks[g.block].rigid) return 0.0;
    g.x += g.v * dt_;
    return g.v.squaredNorm();
  };
  for_owned_gridpoint_ranges(m_, [&](int first, int last) {
    speed2 = std::max(speed2, threaded_max(s_.threads, first, last, move_gridpoint));
  });
  auto move_block = [&](std::ptrdiff_t bi) {
    Block& b = m_.blocks[static_cast<std::size_t>(bi)];
    double fastest = 0.0;
    if (!b.rigid) return fastest;
    b.xc += b.vc * dt_;
    b.theta += b.omega * dt_;
    const double c = std::cos(b.theta), s = std::sin(b.theta);
    // A gridpoint's velocity is its chord over the step (rigid_chord.hpp): the contacts take their
    // increments from it, and the tangent left pre-stressed joints between turning blocks drifting
    // from their geometry.
    const RigidChord chord(b.omega, dt_);
    for (int k = 0; k < b.n_gp; ++k) {
      GridPoint& g = m_.gp[b.first_gp + k];
      const Vec2& r0 = b.rest_offsets[k];
      const Vec2 r(c * r0.x() - s * r0.y(), s * r0.x() + c * r0.y());
      g.x = b.xc + r;
      g.v = chord.velocity(b.vc, r);
      fastest = std::max(fastest, g.v.squaredNorm());
    }
    return fastest;
  };
  for_owned_block_ranges(m_, [&](int first, int last) {
    speed2 = std::max(speed2, threaded_max(s_.threads, first, last, move_block));
  });
  // The largest speed of all processes, so that every one refreshes at the same step (and the
  // result does not depend on the number of processes).
  double speed = std::sqrt(speed2);
  if (comm_.size() > 1) speed = -comm_.min(-speed);
  travel_since_refresh_ += speed * dt_;
  max_speed_ = speed;
  comm_.forward(m_);
  energy_.after_step(m_, EnergyMasses{inertial_mass_, block_mass_, block_inertia_}, dt_, beta);
  if (comm_.size() > 1 && energy_.tracking()) sum_energy();
  m_.time += dt_;
  stage_time_ += dt_;
  ++m_.step;
  // Stop at the first non-finite force. A non-finite position that no force has seen yet (a
  // prescribed NaN velocity) is refused by the broad phase at the next refresh.
  if (nonfinite_) check_state();
  // Two points approaching each other close their gap by at most twice the travel; once that
  // could exceed the detection tolerance (the margin beyond the rounding within which pairs are
  // found), a pair not yet detected could touch unseen: a fast block (one falling into a drift)
  // would strike deep into another and explode the step.
  const double margin = m_.contacts.tolerance > 0.0 ? m_.contacts.tolerance : s_.detection.distance;
  if (++steps_since_refresh_ >= s_.refresh_interval || 2.0 * travel_since_refresh_ > margin) refresh_contacts();
}

void Engine::integrate() {
  double unbalanced = 0.0;
  const bool local = damping_.kind == Damping::Kind::local;
  const double a = damping_.local_alpha;
  const double am = damping_.kind == Damping::Kind::rayleigh ? damping_.alpha : 0.0;
  auto damp = [&](double f, double v) { return local ? f - a * std::abs(f) * (v > 0 ? 1.0 : v < 0 ? -1.0 : 0.0) : f; };
  // Local damping of a deformable block acts separately on its mean (rigid-body) motion and on
  // the gridpoints' motion relative to it. Cundall's local damping opposes the sign of the
  // velocity; applied to absolute velocities it would drag a block that slides steadily (the
  // sign never changes, so the damping force is a spurious resistance of alpha*|F| and does not
  // damp the vibration superposed on the sliding). Split this way, a block driven at constant
  // speed feels no drag and its deformation modes are damped as in a static problem. The mean
  // motion itself (and a rigid block's motion) is damped relative to its running average over
  // kDampingWindow steps, so that a rigid-body oscillation superposed on steady sliding is
  // damped too, while a block at rest sees classic local damping.
  const std::size_t nb = m_.blocks.size();
  mean_v_.assign(nb, Vec2::Zero());
  mean_f_.assign(nb, Vec2::Zero());
  mass_sum_.assign(nb, Vec2::Zero());
  if (local) {
    for_owned_gridpoints(m_, [&](int gi) {
      const auto i = static_cast<std::size_t>(gi);
      const GridPoint& g = m_.gp[i];
      if (m_.blocks[g.block].rigid) return;
      const double mi = inertial_mass_[i];
      for (int d = 0; d < 2; ++d) {
        if (d == 0 ? g.fixed_x : g.fixed_y) continue;
        mean_v_[g.block][d] += mi * g.v[d];
        mean_f_[g.block][d] += g.f[d];
        mass_sum_[g.block][d] += mi;
      }
    });
    for (std::size_t b = 0; b < nb; ++b)
      for (int d = 0; d < 2; ++d)
        if (mass_sum_[b][d] > 0.0) mean_v_[b][d] /= mass_sum_[b][d];
  }
  const double w = 1.0 / kDampingWindow;
  for (std::size_t b = 0; b < nb; ++b) {
    const Vec2 v = m_.blocks[b].rigid ? m_.blocks[b].vc : mean_v_[b];
    smooth_v_[b] += w * (v - smooth_v_[b]);
    smooth_w_[b] += w * (m_.blocks[b].omega - smooth_w_[b]);
  }
  auto sgn = [](double v) { return v > 0 ? 1.0 : v < 0 ? -1.0 : 0.0; };
  // Each gridpoint on its own. On several threads the unbalanced forces are kept per gridpoint
  // and added up afterwards in gridpoint order, so that their sum is that of one thread.
  const bool one_thread = s_.threads <= 1;
  if (!one_thread) unbalanced_gp_.resize(2 * m_.gp.size());
  auto update = [&]<bool kOneThread>(std::ptrdiff_t gi) {
    const auto i = static_cast<std::size_t>(gi);
    GridPoint& g = m_.gp[i];
    if (m_.blocks[g.block].rigid) return;
    const double mi = inertial_mass_[i];
    Vec2 f = g.f - am * mi * g.v;
    for (int d = 0; d < 2; ++d) {
      if (d == 0 ? g.fixed_x : g.fixed_y) continue;
      if constexpr (kOneThread) unbalanced += std::abs(f[d]);
      else unbalanced_gp_[2 * i + static_cast<std::size_t>(d)] = std::abs(f[d]);
      double fd = f[d];
      if (local) {
        const double share = mi / mass_sum_[g.block][d];  // this point's share of the block's mean motion
        const double f_mean = share * mean_f_[g.block][d];
        const double f_rel = f[d] - f_mean;
        fd = f[d] - a * std::abs(f_mean) * sgn(mean_v_[g.block][d] - smooth_v_[g.block][d]) - a * std::abs(f_rel) * sgn(g.v[d] - mean_v_[g.block][d]);
      }
      g.v[d] += fd / mi * dt_;
    }
  };
  if (one_thread) {
    for_owned_gridpoints(m_, [&](int i) { update.template operator()<true>(i); });
  } else {
    for_owned_gridpoint_ranges(m_, [&](int first, int last) {
      threaded_for(s_.threads, first, last, [&](std::ptrdiff_t i) { update.template operator()<false>(i); });
    });
    for_owned_gridpoints(m_, [&](int gi) {
      const auto i = static_cast<std::size_t>(gi);
      const GridPoint& g = m_.gp[i];
      if (m_.blocks[g.block].rigid) return;
      if (!g.fixed_x) unbalanced += unbalanced_gp_[2 * i];
      if (!g.fixed_y) unbalanced += unbalanced_gp_[2 * i + 1];
    });
  }
  block_ratio_ = 0.0;
  worst_block_ = 0;
  for_owned_blocks(m_, [&](int bii) {
    const auto bi = static_cast<std::size_t>(bii);
    Block& b = m_.blocks[bi];
    if (!b.rigid) return;
    Vec2 f = Vec2::Zero();
    double mom = 0.0, magnitudes = 0.0;
    for (int k = 0; k < b.n_gp; ++k) {
      const GridPoint& g = m_.gp[b.first_gp + k];
      f += g.f;
      mom += cross(g.x - b.xc, g.f);
      magnitudes += g.f.norm();
    }
    f += b.mass * m_.gravity;
    applied_sum_ += b.mass * m_.gravity.norm();
    magnitudes += b.mass * m_.gravity.norm();
    b.fc = f;
    b.moment = mom;
    if (b.fixed) return;
    const double fx = b.prescribed & Block::kDriveX ? 0.0 : f.x(), fy = b.prescribed & Block::kDriveY ? 0.0 : f.y();
    const double own = magnitudes > 0.0 ? std::hypot(fx, fy) / magnitudes : 0.0;
    if (own > block_ratio_) {
      block_ratio_ = own;
      worst_block_ = static_cast<int>(bi);
    }
    const double mi = block_mass_[bi], ii = block_inertia_[bi];
    f -= am * mi * b.vc;
    mom -= am * ii * b.omega;
    if (!(b.prescribed & Block::kDriveX)) {
      unbalanced += std::abs(f.x());
      b.vc.x() += damp(f.x(), b.vc.x() - smooth_v_[bi].x()) / mi * dt_;
    }
    if (!(b.prescribed & Block::kDriveY)) {
      unbalanced += std::abs(f.y());
      b.vc.y() += damp(f.y(), b.vc.y() - smooth_v_[bi].y()) / mi * dt_;
    }
    if (!(b.prescribed & Block::kDriveSpin) && ii > 0.0) b.omega += damp(mom, b.omega - smooth_w_[bi]) / ii * dt_;
  });
  unbalanced_ = unbalanced;  // this process's part; step() sums them
}

void Engine::run_steps(long n, bool check_at_end) {
  for (long i = 0; i < n; ++i) {
    step();
    if (m_.step % 1000 == 0) check_state();
  }
  if (check_at_end) check_state();
}

std::string Engine::fastest_gridpoint() const {
  // Each process's fastest owned gridpoint (speed, position, block position), then the fastest of
  // all (ties to the lower block position, so that the answer does not depend on the processes).
  double mine[4] = {-1.0, 0.0, 0.0, -1.0};
  for_owned_gridpoints(m_, [&](int i) {
    const GridPoint& g = m_.gp[static_cast<std::size_t>(i)];
    const double v = g.v.norm();
    if (v > mine[0] || (v == mine[0] && g.block < mine[3])) {
      mine[0] = v;
      mine[1] = g.x.x();
      mine[2] = g.x.y();
      mine[3] = g.block;
    }
  });
  std::vector<double> all;
  comm_.gather_all(mine, 4, all);
  std::size_t best = 0;
  for (std::size_t r = 4; r < all.size(); r += 4)
    if (all[r] > all[best] || (all[r] == all[best] && all[r + 3] < all[best + 3])) best = r;
  if (all[best + 3] < 0.0) return "no gridpoint";
  std::ostringstream os;
  os.precision(3);
  os << "block '" << m_.blocks[static_cast<std::size_t>(all[best + 3])].name << "' near (" << std::fixed << all[best + 1] << ", "
     << all[best + 2] << ") m at " << std::defaultfloat << all[best] << " m/s";
  return os.str();
}

void Engine::check_state() {
  // Each process checks what it owns; the first problem found (in process order) stops all.
  std::string problem;
  for_owned_gridpoints(m_, [&](int i) {
    const GridPoint& g = m_.gp[static_cast<std::size_t>(i)];
    if (!problem.empty() || (g.x.allFinite() && g.v.allFinite() && g.v.norm() <= s_.velocity_limit)) return;
    std::ostringstream os;
    os << "at step " << m_.step << " (time " << m_.time << " s): gridpoint " << g.local << " of block '"
       << m_.blocks[g.block].name << "' has " << (g.v.allFinite() ? "a runaway velocity " : "a non-finite state ")
       << "|v| = " << g.v.norm() << " m/s near (" << g.x.x() << ", " << g.x.y() << ")";
    // The contact with the largest stress on that block is the usual culprit.
    const Contact* worst = nullptr;
    for (const Contact& c : m_.contacts.items)
      if ((c.key.point_block == m_.blocks[g.block].id || m_.blocks[c.other].id == m_.blocks[g.block].id) &&
          (!worst || !std::isfinite(c.response.sigma_n) || std::abs(c.response.sigma_n) > std::abs(worst->response.sigma_n)))
        worst = &c;
    if (worst)
      os << "; most loaded contact: point " << worst->key.point_local << " of block " << worst->key.point_block
         << " on block " << worst->key.other_block << " (sigma_n = " << worst->response.sigma_n << " Pa)";
    os << ". Time step " << dt_ << " s; check stiffnesses, masses and the time step.";
    problem = os.str();
  });
  on_all_processes([&] {
    if (!problem.empty()) throw InstabilityError(problem);
  });
  if (m_.step - last_good_.step >= kGoodStateInterval) last_good_.take(m_);
}

double Engine::kinetic_energy() const {
  double e = 0.0;
  for_owned_gridpoints(m_, [&](int i) {
    const GridPoint& g = m_.gp[static_cast<std::size_t>(i)];
    if (!m_.blocks[g.block].rigid) e += 0.5 * g.mass * g.v.squaredNorm();
  });
  for_owned_blocks(m_, [&](int bi) {
    const Block& b = m_.blocks[static_cast<std::size_t>(bi)];
    if (b.rigid) e += 0.5 * b.mass * b.vc.squaredNorm() + 0.5 * b.inertia * b.omega * b.omega;
  });
  comm_.sum(&e, 1);
  return e;
}

ModelSnapshot Engine::snapshot() const {
  ModelSnapshot s;
  s.take(m_);
  return s;
}

void Engine::restore(const ModelSnapshot& s) { s.put(m_); }

void ModelSnapshot::take(const Model& m) {
  // Copy-assignment keeps each vector's storage when it is large enough.
  gp = m.gp;
  zones = m.zones;
  contacts.items = m.contacts.items;
  contacts.states = m.contacts.states;
  blocks.resize(m.blocks.size());
  for (std::size_t b = 0; b < blocks.size(); ++b) {
    const Block& B = m.blocks[b];
    blocks[b] = BlockMotion{B.xc, B.vc, B.fc, B.theta, B.omega, B.moment, B.fixed, B.prescribed};
  }
  time = m.time;
  step = m.step;
}

bool ModelSnapshot::put(Model& m) const {
  if (blocks.size() != m.blocks.size() || gp.size() != m.gp.size() || zones.size() != m.zones.size()) return false;
  m.gp = gp;
  m.zones = zones;
  for (std::size_t b = 0; b < blocks.size(); ++b) {
    Block& B = m.blocks[b];
    const BlockMotion& s = blocks[b];
    B.xc = s.xc;
    B.vc = s.vc;
    B.fc = s.fc;
    B.theta = s.theta;
    B.omega = s.omega;
    B.moment = s.moment;
    B.fixed = s.fixed;
    B.prescribed = s.prescribed;
  }
  m.contacts.restore(ContactList(contacts));
  m.time = time;
  m.step = step;
  return true;
}

}  // namespace rockdem
