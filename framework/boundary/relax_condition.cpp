#include "framework/boundary/relax_condition.hpp"

#include <algorithm>

namespace rockdem {

RelaxCondition::RelaxCondition(std::vector<std::pair<int, Vec2>> forces, long steps)
    : forces_(std::move(forces)), steps_(std::max(1L, steps)) {}

std::string RelaxCondition::describe(const Model&) const {
  return "excavation relax: the removed blocks' forces on " + std::to_string(forces_.size()) +
         " gridpoints, reduced to zero over " + std::to_string(steps_) + " steps";
}

double RelaxCondition::forces(Model& m, double) {
  ++done_;
  const double factor = std::max(0.0, 1.0 - static_cast<double>(done_) / static_cast<double>(steps_));
  if (factor == 0.0) return 0.0;
  double applied = 0.0;
  for (const auto& [g, f] : forces_) {
    if (!m.part.owns(m.gp[g].block)) continue;  // another process's (partition.hpp)
    m.gp[g].f += factor * f;
    applied += factor * f.norm();
  }
  return applied;
}

bool RelaxCondition::renumber(const Renumbering& r) {
  std::vector<std::pair<int, Vec2>> kept;
  for (const auto& [g, f] : forces_)
    if (r.gp[static_cast<std::size_t>(g)] >= 0) kept.emplace_back(r.gp[static_cast<std::size_t>(g)], f);
  forces_ = std::move(kept);
  return true;
}

}  // namespace rockdem
