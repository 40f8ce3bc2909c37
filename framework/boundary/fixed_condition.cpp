#include "framework/boundary/fixed_condition.hpp"

#include <sstream>

#include "framework/boundary/condition_kinds.hpp"
#include "framework/boundary/velocity_condition.hpp"
#include "framework/core/error.hpp"

namespace rockdem {

FixedCondition::FixedCondition(FaceSelection sel, bool fix_x, bool fix_y, bool whole)
    : sel_(std::move(sel)), fx_(fix_x), fy_(fix_y), rigid_(whole) {}

std::string FixedCondition::describe(const Model& m) const {
  std::ostringstream os;
  os << "fixed " << (fx_ ? "x" : "") << (fy_ ? "y" : "") << " on block '" << m.blocks[sel_.block].name << "'"
     << (rigid_ ? std::string() : " (" + std::to_string(sel_.points.size()) + " gridpoints)");
  return os.str();
}

void FixedCondition::setup(Model& m) {
  if (rigid_) {
    m.blocks[sel_.block].fixed = true;
    return;
  }
  for (int g : sel_.points) {
    m.gp[g].fixed_x = m.gp[g].fixed_x || fx_;
    m.gp[g].fixed_y = m.gp[g].fixed_y || fy_;
  }
}

void FixedCondition::velocities(Model& m, double) {
  if (rigid_) {
    Block& b = m.blocks[sel_.block];
    b.vc.setZero();
    b.omega = 0.0;
    return;
  }
  for (int g : sel_.points) {
    if (fx_) m.gp[g].v.x() = 0.0;
    if (fy_) m.gp[g].v.y() = 0.0;
  }
}

namespace {

std::unique_ptr<BoundaryCondition> make_fixed(const ConditionInput& in) {
  bool fx = true, fy = true;
  if (const ConditionValue* comps = in.value("components")) {
    fx = fy = false;
    for (std::size_t i = 0; i < comps->names.size(); ++i) {
      const std::string& s = comps->names[i];
      if (s == "x") fx = true;
      else if (s == "y") fy = true;
      else throw InputError(comps->name_wheres[i] + ": unknown component '" + s + "'; valid: x, y");
    }
  }
  if (in.rigid && !(fx && fy)) {
    // Holding one component of a rigid block: a zero velocity on that component only.
    const bool spin = in.by_region && !in.selection.edges.empty();
    return std::make_unique<VelocityCondition>(in.selection, true,
                                               fx ? std::optional(TimeFunction::constant(0.0)) : std::nullopt,
                                               fy ? std::optional(TimeFunction::constant(0.0)) : std::nullopt,
                                               spin ? std::optional(TimeFunction::constant(0.0)) : std::nullopt);
  }
  return std::make_unique<FixedCondition>(in.selection, fx, fy, in.rigid);
}

using Type = ConditionKey::Type;

// The rank places the kind in messages' list: fixed, velocity, traction, quiet.
const ConditionKindRegistrar fixed_kind{10, ConditionKind{
    "fixed", "gridpoints (or a whole rigid block) held in place",
    {{"components", Type::names, Dimension::dimensionless, "components held, [\"x\"], [\"y\"] or both (default)"}},
    true, make_fixed, {}}};

}  // namespace
}  // namespace rockdem
