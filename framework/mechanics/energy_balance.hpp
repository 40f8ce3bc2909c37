#pragma once
// The energy balance of a run: work put in by gravity and the boundaries, energy stored as
// kinetic, zone strain and contact elastic energy, and energy dissipated by joint slip and by
// damping. The engine feeds it once per step when it is tracking (Engine::energy() starts it).
//
// Staggering. Central differences keep forces and positions at whole steps n and velocities at
// half steps. For a linear spring the quantity 1/2 m v(n-1/2).v(n+1/2) + potential(x_n) is exactly
// conserved by the scheme, and the kinetic part changes from step n-1 to n by the trapezoidal
// work 1/2 (F(n-1) + F(n)).(x_n - x(n-1)). Every term here is therefore taken at whole step n:
// kinetic energy from the two half-step velocities around it, works and damping losses as
// trapezoids of the forces at both ends of each displacement x(n) - x(n-1) = v(n-1/2) dt, zone
// strain work as 1/2 (sigma(n-1) + sigma(n)) : (eps(n) - eps(n-1)). With the half-step kinetic
// energy and F(n).v dt the balance would wobble by a fraction of order omega dt of the energy in
// a stiff contact, which is about all of it while a block bounces.
#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "framework/model/model.hpp"

namespace rockdem {

struct EnergyTerms {
  double kinetic = 0.0;          // whole-step kinetic energy, physical masses [J/m]
  double strain = 0.0;           // work done on the zones by their stresses since the start [J/m]
  double contact = 0.0;          // elastic energy in the contacts now, minus at the start [J/m]
  double gravity_work = 0.0;     // work done by gravity [J/m]
  double boundary_work = 0.0;    // work of boundary tractions and of the reactions of prescribed
                                 // velocities (fixed gridpoints do none) [J/m]
  double slip = 0.0;             // dissipated by joint slip (the laws' `dissipated` x length) [J/m]
  double damping = 0.0;          // dissipated by local and Rayleigh damping [J/m]
  double kinetic_start = 0.0;    // kinetic energy at the start of the accounting [J/m]
  double contact_start = 0.0;    // contact elastic energy at the start [J/m]

  double work_in() const { return gravity_work + boundary_work; }
  // Stored and dissipated since the start.
  double accounted() const { return (kinetic - kinetic_start) + strain + contact + slip + damping; }
  // work in - (stored + dissipated) [J/m].
  double imbalance() const { return work_in() - accounted(); }
  // The largest magnitude of the terms now (the error's reference keeps the largest ever).
  double largest() const {
    return std::max({std::abs(gravity_work), std::abs(boundary_work), std::abs(kinetic - kinetic_start), std::abs(strain),
                     std::abs(contact), std::abs(slip), std::abs(damping)});
  }
  // The imbalance relative to the largest magnitude any term has reached since the start (0
  // while nothing has happened). Relative to the terms' present values it would blow up whenever
  // they all pass near zero, e.g. a bouncing block at the top of its flight.
  double error = 0.0;
  // Not a term of the balance but a measure of one of its errors: how much the contact refreshes
  // changed the contacts' elastic energy with their stresses as they were (the lengths shared out
  // again, contacts made with a neighbour's state or dropped while loaded). No force does that
  // work, so it shows in the imbalance; imbalance + refresh is what is left without it [J/m].
  double refresh = 0.0;
};

// What the engine hands over each step: its inertial masses (mass scaling included).
struct EnergyMasses {
  const std::vector<double>& gp;  // per gridpoint of deformable blocks
  const std::vector<double>& block, &inertia;  // per rigid block
};

class EnergyBalance {
 public:
  bool tracking() const { return on_; }
  // The accounting starts at the end of the next completed step (that whole step is the reference).
  void start() { on_ = true; started_ = false; t_ = EnergyTerms{}; }
  const EnergyTerms& terms() const { return t_; }
  double scale() const { return scale_; }

  // For a checkpoint: what the next step's trapezoids need from the last one, per gridpoint,
  // rigid block and zone (the items this process owns; zero elsewhere, so that the processes'
  // arrays add up to the whole model's), and whether the reference step has been taken. Empty
  // when not tracking. The terms themselves are saved by the engine (summed over the processes).
  std::map<std::string, std::vector<double>> saved_items(const Model& m) const;
  // Puts the state back, tracking, with `terms` and `scale` (the whole model's on one process,
  // zero terms on the others: the processes' terms add up to the whole model's). False, with
  // nothing changed, when `a` holds no energy state or its arrays do not fit the model.
  bool restore(const Model& m, const std::map<std::string, std::vector<double>>& a, const EnergyTerms& terms, double scale);

  // Calls from Engine::step(), in this order; each returns at once when not tracking.
  void after_zone_forces(const Model& m, double beta);  // g.f holds the zone forces alone
  void before_boundary_forces(const Model& m);   // g.f holds zone and contact forces; v is v(n-1/2)
  void after_boundary_forces(const Model& m);    // g.f now also holds boundary forces
  // After the velocity update, prescribed velocities and the position update. `dt` is the step
  // just taken; `beta` the Rayleigh stiffness coefficient (its dissipation is the zone forces'
  // work that the zone stresses did not store).
  void after_step(const Model& m, const EnergyMasses& masses, double dt, double beta);
  // Around a contact refresh (Engine::refresh_contacts): the contacts' elastic energy before and
  // after it, as contact_energy counts it. The change goes to `refresh` and at once to `contact`
  // (which the next step would find anyway), so that a sample taken between the refresh and that
  // step, as at the start of a stage, has both or neither.
  static double stored_in_contacts(const Model& m) { return contact_energy(m, nullptr); }
  void refreshed(double before, double after);

 private:
  static double contact_energy(const Model& m, double* slip_increment);

  bool on_ = false, started_ = false;
  EnergyTerms t_;
  double scale_ = 0.0;  // largest magnitude any term has reached (the error's reference)
  double dt_prev_ = 0.0;
  // Per gridpoint: boundary force now and at the previous step, the force not explained by the
  // applied ones (damping on free components, reactions on prescribed ones) at the previous step,
  // the half-step velocity before this step's update; the zone forces when Rayleigh damping acts.
  std::vector<Vec2> f_bc_, f_bc_prev_, r_prev_, v_old_, f_zone_, f_zone_prev_;
  // Per rigid block: the same for (x, y, rotation).
  std::vector<Eigen::Vector3d> rb_prev_, vb_old_;
  // Per zone: stress and strain of the previous step.
  std::vector<Voigt3> sig_prev_, eps_prev_;
};

}  // namespace rockdem
