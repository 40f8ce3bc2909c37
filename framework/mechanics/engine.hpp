#pragma once
// Explicit central-difference time stepping of a block model (Cundall & Hart 1985; UDEC):
// velocities live at half steps, positions at whole steps. One cycle: contact geometry ->
// zone stresses -> contact forces through the joint laws -> external forces -> damping ->
// velocities and positions. The same code runs whatever the decomposition (it never sees MPI).
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "framework/boundary/conditions.hpp"
#include "framework/contact/detection.hpp"
#include "framework/mechanics/energy_balance.hpp"
#include "framework/mechanics/engine_settings.hpp"
#include "framework/model/communication.hpp"
#include "framework/model/model.hpp"

namespace rockdem {

// The part of a block that changes while stepping; its geometry, name and material do not.
struct BlockMotion {
  Vec2 xc = Vec2::Zero(), vc = Vec2::Zero(), fc = Vec2::Zero();
  double theta = 0.0, omega = 0.0, moment = 0.0;
  bool fixed = false;
  std::uint8_t prescribed = 0;
};

// A copy of everything that evolves while stepping, for the "last good state" of instability
// reports. take() copies into the arrays the snapshot already holds, so once taken it does not
// allocate again unless the model has grown (contacts, say), and it copies no block geometry.
struct ModelSnapshot {
  std::vector<GridPoint> gp;
  std::vector<Zone> zones;
  std::vector<BlockMotion> blocks;
  ContactList contacts;
  double time = 0.0;
  long step = 0;

  void take(const Model& m);
  // Puts the state back. A snapshot whose arrays no longer match the model's (blocks removed
  // since it was taken) is not applied: returns false and leaves the model as it is.
  bool put(Model& m) const;
};

class Engine {
 public:
  // `comm`: the other processes of a domain-decomposed run (communication.hpp); by default none.
  Engine(Model& m, EngineSettings s, Communication& comm = serial_communication());

  void add_condition(std::unique_ptr<BoundaryCondition> bc);
  const std::vector<std::unique_ptr<BoundaryCondition>>& conditions() const { return bcs_; }

  // Start a stage: activates the boundary conditions listed for it, resets the stage clock, detects
  // contacts and computes masses and the time step.
  // `resuming`: the stage is taken up within, from a checkpoint (its start passed the checks made
  // here once; a time step forced above the stable one is not refused again mid-stage).
  void begin_stage(const std::string& name, const Damping& d, bool resuming = false);
  void step();
  // Run `n` steps; stops early with InstabilityError (after keeping the last good state).
  // `check_at_end` false: the state check that ends every call is left to a later call (a
  // caller that splits a chunk of steps keeps the checks where the whole chunk has them).
  void run_steps(long n, bool check_at_end = true);

  double dt() const { return dt_; }
  // The step the last step moved the points by: dt() may have changed since, at the contact
  // refresh that ends a step (0 before the first step of this run).
  double moved_dt() const { return moved_dt_; }
  // The inertial mass mass scaling added, as a fraction of the model's mass, at the last refresh
  // (0 without scaling). Dynamic stages that scale the masses of their smallest zones say it.
  double added_mass_fraction() const { return physical_mass_ > 0.0 ? scaled_mass_ / physical_mass_ - 1.0 : 0.0; }
  double stage_time() const { return stage_time_; }
  const std::string& stage() const { return stage_; }
  // The largest gridpoint speed of the last step [m/s]: far above the ground motion's and free
  // fall's in a dynamic stage, it shows a numerical problem the runaway limit does not catch.
  double max_speed() const { return max_speed_; }
  // Unbalanced-force ratio: sum of |net force| over sum of |applied and contact forces|.
  double unbalanced_ratio() const { return ratio_; }
  // The largest unbalanced-force ratio of a single free rigid block (its net force over the sum of
  // the magnitudes of the forces on it, translation only) in the last step, and that block.
  double block_unbalanced_ratio() const { return block_ratio_; }
  int worst_block() const { return worst_block_; }
  // Where the model moves fastest now, in words: the gridpoint with the largest speed, its block
  // and its position, e.g. "block 'rm.98' near (5.155, 6.000) m at 0.0155 m/s". Said when a stage
  // does not reach equilibrium, so that a user sees where it chatters without reading the state.
  // A collective call when decomposed (every process gets the same answer).
  std::string fastest_gridpoint() const;
  // Contact force exerted on a block (sum over its contacts) in the last step [N/m].
  Vec2 contact_force_on(int block) const;
  double kinetic_energy() const;  // of the whole model (a collective call when decomposed)
  // The energy balance since the first call (energy_balance.hpp). The accounting costs a few
  // passes over the gridpoints per step, so it runs only once something has asked for it: the
  // first call starts it (a history of it is first sampled before the first step of a run).
  // When decomposed, every process must call it first at the same step (the terms are summed
  // over the processes every step from then on).
  const EnergyTerms& energy() const;

  // What the last step left outside the Model that histories read (the unbalanced ratios, the
  // largest speed, the contact force on every block), for a checkpoint: a run restarted from it
  // samples the same values before its first step as the uninterrupted run did. A collective
  // call when decomposed (each block's force comes from the process owning it).
  std::map<std::string, std::vector<double>> saved_state() const;
  // Puts it back (a checkpoint without it leaves the engine as it is); InputError naming `file`
  // when it does not fit.
  void restore_state(const std::map<std::string, std::vector<double>>& a, const std::string& file);

  // Whether the last step ended with a contact detection (or no step has run since one): the
  // only moments a checkpoint taken within a stage can be resumed from exactly, because a
  // restarted stage begins with a detection of its own (which, on the same positions and
  // contacts, finds them again and recomputes the same time step and masses).
  bool just_refreshed() const { return steps_since_refresh_ == 0; }
  // What a stage carries from step to step that begin_stage sets afresh: the stage clock and the
  // damping's running averages, for a checkpoint written within a stage (each block's values from
  // the process owning it; a collective call when decomposed).
  std::map<std::string, std::vector<double>> saved_stage_state() const;
  // After begin_stage of the stage the checkpoint was written in: puts them back. InputError
  // naming `file` when the checkpoint has none or they do not fit the model.
  void resume_stage(const std::map<std::string, std::vector<double>>& a, const std::string& file);

  // In a domain-decomposed run, at a contact detection (just_refreshed()): asks the communication
  // whether blocks should change owner (Communication::plan_owners: the load out of balance
  // beyond `limit`, 0 never, or blocks that moved among another process's blocks) and, if so,
  // hands them over: what only owners hold (the contact force on each block, the damping's
  // averages, the energy balance's per-item state) and the whole model's state go to every process, the new owners take over, and the detection is made again
  // (on the same state it finds the same contacts, masses and step, as a restart within a stage
  // does), so that no result changes. Checks the state first; the state handed over becomes the
  // last good one. A collective call; does nothing in a serial run.
  OwnerChange rebalance(double limit);

  // Blocks taken out while a stage runs (a stage's scale_off), at a contact detection: checks the
  // state, makes the whole model's state current on every process (decomposed), calls `remove`,
  // which removes the blocks from the model and renumbers what refers to positions, and carries
  // the engine's own per-block and per-gridpoint state (damping averages, contact forces on
  // blocks, masses) to the new positions; then detects contacts again and keeps the result as the
  // last good state. The energy balance starts its per-item arrays afresh at the next step (the
  // blocks' kinetic and contact energy leave the model with them). Collective when decomposed.
  void take_out(const std::function<Renumbering()>& remove);

  const ModelSnapshot& last_good() const { return last_good_; }
  ModelSnapshot snapshot() const;
  void restore(const ModelSnapshot& s);
  // Detection + time step update. `account`: the change of the contacts' elastic energy goes to
  // the energy balance's `refresh` (not after blocks were taken out, whose contacts' energy leaves
  // the accounting, or a change of owners, which finds the same contacts again).
  void refresh_contacts(bool account = true);
  Model& model() { return m_; }
  const Model& model() const { return m_; }
  const EngineSettings& settings() const { return s_; }
  Communication& communication() const { return comm_; }
  // The stable time step masses are scaled to (0: real masses), from the next begin_stage on.
  void set_mass_scaling_dt(double dt) { s_.mass_scaling_dt = dt; }

 private:
  void compute_time_step();
  void contact_forces();
  void integrate();
  void check_state();
  void sum_energy();  // the energy terms of all processes (decomposed runs)
  // The contact force on each block (x, y by position), its owner's on every process (collective).
  std::vector<double> block_forces() const;
  // Runs f; in a decomposed run an error raised by it on any process is raised on every process
  // (with that process's message), so that none waits for the others.
  template <class F>
  void on_all_processes(F&& f);

  Model& m_;
  EngineSettings s_;
  Communication& comm_;
  std::vector<std::unique_ptr<BoundaryCondition>> bcs_;
  std::vector<BoundaryCondition*> active_;
  Damping damping_;
  std::string stage_;
  double stage_time_ = 0.0;
  double dt_ = 0.0;
  double moved_dt_ = 0.0;
  double critical_dt_ = 0.0;  // stable step before dt_safety, at the last refresh
  double physical_mass_ = 0.0, scaled_mass_ = 0.0;  // the whole model's, at the last refresh [kg/m]
  double ratio_ = 0.0;
  double block_ratio_ = 0.0;
  int worst_block_ = 0;
  double applied_sum_ = 0.0;
  double unbalanced_ = 0.0;  // this process's sum of |net force| in the last integrate()
  std::vector<double> step_sums_;  // every process's step quantities (step())
  bool nonfinite_ = false;  // the last step's force sums were NaN or inf
  std::vector<double> inertial_mass_;      // per gridpoint (after mass scaling)
  std::vector<double> previous_mass_;      // the same before the last time-step computation
  bool momentum_rule_ = false;             // the last computation applied the momentum rule
  // Set by begin_stage (not when resuming): the next time-step computation is a stage's first,
  // whose masses the stage's own scaling sets, and the momentum rule applies to every gridpoint
  // and rigid block whatever the damping.
  bool stage_start_ = false;
  std::vector<double> previous_block_mass_, previous_block_inertia_;
  std::vector<double> dashpot_;            // per gridpoint: viscous boundaries' dashpots [N s/m per m]
  std::vector<double> block_mass_, block_inertia_;
  std::vector<Vec2> block_contact_force_;  // per block, last step
  std::vector<char> acting_;               // per contact, this step (threaded contact_forces)
  std::vector<double> unbalanced_gp_;      // per gridpoint, |f_x| and |f_y| this step (integrate)
  std::vector<Vec2> mean_v_, mean_f_, mass_sum_;  // per block, for local damping
  std::vector<Vec2> smooth_v_;                    // running average of each block's (mean) velocity
  std::vector<double> smooth_w_;                  // and spin
  static constexpr double kDampingWindow = 1000.0;  // steps
  ModelSnapshot last_good_;
  // Steps between two copies of the last good state; the state is checked more often (every
  // run_steps call), the copy is only kept every so many steps (docs/performance.md, measured).
  static constexpr long kGoodStateInterval = 1000;
  mutable EnergyBalance energy_;  // started by the first energy() call
  EnergyTerms energy_sum_;  // its terms summed over the processes
  double energy_scale_ = 0.0;  // the largest summed term so far
  long steps_since_refresh_ = 0;
  // The farthest any gridpoint can have moved since the last detection (sum over steps of the
  // largest speed times dt): contacts are refreshed before two points could close the detection
  // tolerance between them (a Verlet-style skin), not only every refresh_interval steps.
  double travel_since_refresh_ = 0.0;
  double max_speed_ = 0.0;  // the largest gridpoint speed of the last step, over every process [m/s]
};

}  // namespace rockdem
