#include "framework/simulation/stage.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "framework/core/error.hpp"

namespace rockdem {

void StageJointModels::put_in_force(Case& c, std::size_t stage) const {
  c.model.contacts.models = case_models_;
  for (std::size_t s = 0; s <= stage; ++s)
    for (const auto& [index, model] : c.stages[s].joint_models) c.model.contacts.models[static_cast<std::size_t>(index)] = model;
}

StageRunner::StageRunner(Case& c, Engine& e, const StageJointModels& joints, std::size_t index, bool resuming)
    : st_(c.stages[index]), e_(e) {
  joints.put_in_force(c, index);
  e.set_mass_scaling_dt(st_.mass_scaling_dt.value_or(c.settings.mass_scaling_dt));
  // The stage's ground motions reach every condition before its setup, so that a stage with
  // duration = "auto" lasts as long as its motions.
  std::vector<BoundaryCondition::StageMotion> played;
  for (const auto& m : st_.motions) played.push_back({c.motions[static_cast<std::size_t>(m.index)].get(), m.factor});
  for (const auto& bc : e.conditions())
    if (bc->active_in(st_.name)) bc->set_motions(played);
  e.begin_stage(st_.name, st_.damping, resuming);
  duration_ = st_.duration;
  if (st_.until == StageSpec::Until::duration && st_.auto_duration) {
    duration_ = 0.0;
    for (const auto& bc : e.conditions())
      if (bc->active_in(st_.name)) duration_ = std::max(duration_, bc->history_duration());
    if (!(duration_ > 0.0 && std::isfinite(duration_)))
      throw InputError(c.file + ": stage '" + st_.name + "' has duration = \"auto\" but no finite velocity history is active in it");
  }
  planned_ = st_.until == StageSpec::Until::steps ? st_.steps
             : st_.until == StageSpec::Until::duration ? static_cast<long>(std::ceil(duration_ / e.dt()))
                                                       : st_.max_steps;
}

bool StageRunner::done(long n) const {
  switch (st_.until) {
    case StageSpec::Until::steps: return n >= st_.steps;
    case StageSpec::Until::duration: return e_.stage_time() >= duration_ - 0.5 * e_.dt();
    case StageSpec::Until::equilibrium: {
      const bool blocks_ok = st_.block_ratio <= 0.0 || e_.block_unbalanced_ratio() < st_.block_ratio;
      const bool converged = n >= 100 && e_.unbalanced_ratio() < st_.ratio && blocks_ok;
      if (!converged && n >= st_.max_steps) {
        std::string why = "unbalanced-force ratio " + std::to_string(e_.unbalanced_ratio()) + (e_.unbalanced_ratio() < st_.ratio ? " <= " : " > ") +
                          std::to_string(st_.ratio);
        if (st_.block_ratio > 0.0 && !blocks_ok)
          why += "; block '" + e_.model().blocks[static_cast<std::size_t>(e_.worst_block())].name + "' has its own ratio " +
                 std::to_string(e_.block_unbalanced_ratio()) + " > block_ratio " + std::to_string(st_.block_ratio);
        // Where it still moves: the usual place to look (a chattering contact, a loose block).
        why += "; fastest gridpoint: " + e_.fastest_gridpoint();
        if (st_.continue_at_max_steps) {
          unconverged_ = "stage '" + st_.name + "' ended at max_steps = " + std::to_string(st_.max_steps) +
                         " without equilibrium (" + why + "); at_max_steps = \"continue\": the run goes on";
          return true;
        }
        throw InstabilityError("stage '" + st_.name + "' did not reach equilibrium (" + why + ") within max_steps = " +
                               std::to_string(st_.max_steps) + " (at_max_steps = \"continue\" ends the stage there and goes on)");
      }
      return converged;
    }
  }
  return false;
}

double StageRunner::seconds_left(long n, double rate) const {
  double left = NAN;
  if (st_.until == StageSpec::Until::duration) left = (duration_ - e_.stage_time()) / e_.dt() / rate;
  if (st_.until == StageSpec::Until::steps) left = static_cast<double>(st_.steps - n) / rate;
  return left;
}

}  // namespace rockdem
