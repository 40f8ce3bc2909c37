#include "framework/boundary/in_situ_condition.hpp"

#include "framework/boundary/condition_kinds.hpp"
#include "framework/core/error.hpp"

namespace rockdem {

InSituCondition::InSituCondition(FaceSelection sel, StressField field) : sel_(std::move(sel)), field_(field) {}

std::string InSituCondition::describe(const Model& m) const {
  return "in-situ traction on block '" + m.blocks[sel_.block].name + "' (" + std::to_string(sel_.edges.size()) + " edges)";
}

double InSituCondition::forces(Model& m, double) {
  double applied = 0.0;
  for_each_edge(m, sel_, [&](int ga, int gb, const Vec2& d) {
    const double len = d.norm();
    if (!(len > 0.0)) return;
    const Vec2 out = Vec2(d.y(), -d.x()) / len;  // outward unit normal (counter-clockwise loop)
    // The field is linear along the edge, so the consistent nodal loads of a linear traction
    // (L/6 (2 ta + tb) and L/6 (ta + 2 tb)) give its resultant and its moment exactly; a rigid
    // block then feels no spurious moment from a stress that grows with depth.
    const Vec2 ta = field_.traction(m.gp[ga].x, out), tb = field_.traction(m.gp[gb].x, out);
    const Vec2 fa = len / 6.0 * (2.0 * ta + tb), fb = len / 6.0 * (ta + 2.0 * tb);
    m.gp[ga].f += fa;
    m.gp[gb].f += fb;
    applied += fa.norm() + fb.norm();
  });
  return applied;
}

namespace {

std::unique_ptr<BoundaryCondition> make_in_situ(const ConditionInput& in) {
  if (!in.stress_field)
    throw InputError(in.where + ": type = \"in_situ\" loads the boundary with the in-situ stress field, but the case "
                     "has no [in_situ] table; add one (surface, density, surcharge, K) or use type = \"traction\"");
  return std::make_unique<InSituCondition>(in.selection, *in.stress_field);
}

// The rank places the kind in messages' list: fixed, velocity, traction, in_situ, quiet.
const ConditionKindRegistrar in_situ_kind{35, ConditionKind{
    "in_situ", "the traction sigma(x) . n of the case's [in_situ] stress field, varying along the face",
    {}, false, make_in_situ, {}}};

}  // namespace
}  // namespace rockdem
