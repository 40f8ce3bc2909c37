#pragma once
// Running the stages of a case (StageSpec, framework/io/case.hpp) on its engine: which joint
// models are in force, how long a stage runs, and when it is done.
#include <cstddef>
#include <memory>
#include <vector>

#include "framework/io/case.hpp"
#include "framework/mechanics/engine.hpp"

namespace rockdem {

// The joint models in force at each stage: the case's, replaced by a stage's `joints` values from
// that stage on. The case's are kept from before any stage ran, so that a restart beginning in
// the middle of the list puts in force what the uninterrupted run had.
class StageJointModels {
 public:
  explicit StageJointModels(const Case& c) : case_models_(c.model.contacts.models) {}
  void put_in_force(Case& c, std::size_t stage) const;

 private:
  std::vector<std::shared_ptr<const JointModel>> case_models_;
};

// One stage of a case, from its start to its end condition; the caller steps the engine.
class StageRunner {
 public:
  // Starts stage `index`: puts its joint models in force, begins the engine's stage (conditions,
  // contacts, time step) and finds its duration and planned steps. Throws InputError for
  // duration = "auto" without a finite velocity history active in the stage.
  // `resuming`: taken up within the stage from a checkpoint (Engine::begin_stage).
  StageRunner(Case& c, Engine& e, const StageJointModels& joints, std::size_t index, bool resuming = false);

  const StageSpec& spec() const { return st_; }
  // Steps the stage is planned to take (for `equilibrium`, its cap max_steps).
  long planned_steps() const { return planned_; }
  // Whether the stage has ended after `n` of its steps. Throws InstabilityError when an
  // `equilibrium` stage has not converged within max_steps.
  bool done(long n) const;
  // Wall-clock seconds the stage still needs at `rate` steps/s after `n` steps; NaN when unknown
  // (`equilibrium`).
  double seconds_left(long n, double rate) const;
  // After done() returned true: "" when the stage met its end condition, else why an
  // `equilibrium` stage with at_max_steps = "continue" ended at max_steps (for a warning).
  const std::string& unconverged() const { return unconverged_; }

 private:
  const StageSpec& st_;
  const Engine& e_;
  double duration_ = 0.0;  // [s], for `duration`
  long planned_ = 0;
  mutable std::string unconverged_;
};

}  // namespace rockdem
