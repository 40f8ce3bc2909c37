#include "framework/simulation/excavate.hpp"

#include <algorithm>
#include <map>

#include "framework/boundary/relax_condition.hpp"
#include "framework/model/excavation.hpp"

namespace rockdem {
namespace {

// The last contact forces between removed and remaining blocks, on the remaining gridpoints
// (old positions): the force on the point's block and its reaction shared by the edge's ends,
// as Engine::contact_forces applies them.
std::map<int, Vec2> released_forces(const Model& m, const std::vector<char>& gone) {
  std::map<int, Vec2> out;
  // Eigen leaves a default-constructed vector uninitialised, so a gridpoint's sum starts from an
  // explicit zero (out[g] += f added to whatever the memory held: a gradual release then blew up).
  const auto add = [&](int g, const Vec2& f) { out.try_emplace(g, Vec2::Zero()).first->second += f; };
  for (const Contact& c : m.contacts.items) {
    const int pb = static_cast<int>(m.gp[c.point].block);
    if (gone[static_cast<std::size_t>(pb)] == gone[static_cast<std::size_t>(c.other)]) continue;
    if (c.response.open) continue;
    const Vec2 t(c.normal.y(), -c.normal.x());
    const Vec2 f = c.length * (c.response.sigma_n * c.normal - c.response.tau * t);
    if (!gone[static_cast<std::size_t>(pb)]) {
      add(c.point, f);
      continue;
    }
    const Block& B = m.blocks[static_cast<std::size_t>(c.other)];
    const int n = static_cast<int>(B.boundary.size());
    add(B.boundary[c.edge], -(1.0 - c.s) * f);
    add(B.boundary[(c.edge + 1) % n], -c.s * f);
  }
  return out;
}

// Removes the blocks whose ids are in `ids` and renumbers everything that refers to model
// positions; with `relax_steps` > 0 and `relax` given, sets it to the condition that releases
// their contacts' last forces over those steps. The positions removed go to `removed`.
Renumbering remove_and_renumber(Case& c, const std::vector<std::unique_ptr<BoundaryCondition>>& conditions,
                                const std::vector<BlockId>& ids, long relax_steps, const std::string& stage,
                                std::unique_ptr<BoundaryCondition>* relax, std::size_t& removed) {
  Model& m = c.model;
  std::vector<int> positions;
  std::vector<char> gone(m.blocks.size(), 0);
  for (std::size_t b = 0; b < m.blocks.size(); ++b)
    if (std::count(ids.begin(), ids.end(), m.blocks[b].id)) {
      positions.push_back(static_cast<int>(b));
      gone[b] = 1;
    }
  removed = positions.size();
  if (positions.empty()) return {};
  const std::map<int, Vec2> released = relax && relax_steps > 0 ? released_forces(m, gone) : std::map<int, Vec2>{};
  Renumbering r = remove_blocks(m, positions);
  for (const auto& bc : conditions)
    if (!bc->renumber(r)) bc->removed = true;
  for (auto& h : c.histories) {
    if (h.target.block >= 0) h.target.block = r.block[static_cast<std::size_t>(h.target.block)];
    r.points(h.target.points);
  }
  std::vector<std::string> names;
  for (std::size_t b = 0; b < c.block_names.size(); ++b)
    if (!gone[b]) names.push_back(c.block_names[b]);
  c.block_names = std::move(names);
  auto& d = c.direct_shear;
  for (int* b : {&d.loader, &d.top, &d.bottom})
    if (*b >= 0) *b = r.block[static_cast<std::size_t>(*b)];
  for (int& b : d.other_loaders) b = r.block[static_cast<std::size_t>(b)];
  r.points(d.top_face);
  r.points(d.bottom_face);
  if (!released.empty()) {
    std::vector<std::pair<int, Vec2>> forces;
    for (const auto& [g, f] : released) forces.emplace_back(r.gp[static_cast<std::size_t>(g)], f);
    *relax = std::make_unique<RelaxCondition>(std::move(forces), relax_steps);
    (*relax)->stages = {stage};
  }
  return r;
}

}  // namespace

std::size_t excavate(Case& c, const std::vector<std::unique_ptr<BoundaryCondition>>& conditions, const StageSpec& stage,
                     std::unique_ptr<BoundaryCondition>* relax) {
  std::size_t removed = 0;
  remove_and_renumber(c, conditions, stage.excavate, stage.relax_steps, stage.name, relax, removed);
  return removed;
}

Renumbering take_out_blocks(Case& c, const std::vector<std::unique_ptr<BoundaryCondition>>& conditions,
                            const std::vector<BlockId>& ids) {
  std::size_t removed = 0;
  return remove_and_renumber(c, conditions, ids, 0, "", nullptr, removed);
}

}  // namespace rockdem
