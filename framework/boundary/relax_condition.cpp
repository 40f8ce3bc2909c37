#include "framework/boundary/relax_condition.hpp"

#include <algorithm>
#include <string>

#include "framework/core/error.hpp"

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

std::vector<double> RelaxCondition::progress() const {
  std::vector<double> p{static_cast<double>(steps_), static_cast<double>(done_)};
  for (const auto& [g, f] : forces_) p.insert(p.end(), {static_cast<double>(g), f.x(), f.y()});
  return p;
}

std::unique_ptr<RelaxCondition> RelaxCondition::from_progress(const std::vector<double>& p, std::size_t gridpoints) {
  if (p.size() < 2 || (p.size() - 2) % 3 != 0 || !(p[0] >= 1.0) || !(p[1] >= 0.0))
    throw InputError("checkpoint: the excavation relax it holds is damaged (" + std::to_string(p.size()) + " values)");
  std::vector<std::pair<int, Vec2>> forces;
  for (std::size_t k = 2; k + 2 < p.size(); k += 3) {
    if (!(p[k] >= 0.0 && p[k] < static_cast<double>(gridpoints)))
      throw InputError("checkpoint: the excavation relax it holds names gridpoint " + std::to_string(p[k]) + " of " +
                       std::to_string(gridpoints));
    forces.emplace_back(static_cast<int>(p[k]), Vec2(p[k + 1], p[k + 2]));
  }
  auto r = std::make_unique<RelaxCondition>(std::move(forces), static_cast<long>(p[0]));
  r->done_ = static_cast<long>(p[1]);
  return r;
}

}  // namespace rockdem
