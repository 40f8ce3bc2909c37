#include "framework/boundary/velocity_condition.hpp"

#include <algorithm>
#include <cmath>

#include "framework/boundary/condition_kinds.hpp"
#include "framework/core/error.hpp"

namespace rockdem {

VelocityCondition::VelocityCondition(FaceSelection sel, bool whole, std::optional<TimeFunction> vx,
                                     std::optional<TimeFunction> vy, std::optional<TimeFunction> spin)
    : sel_(std::move(sel)), rigid_(whole), vx_(std::move(vx)), vy_(std::move(vy)), spin_(std::move(spin)) {}

std::string VelocityCondition::describe(const Model& m) const {
  std::string s = "velocity on block '" + m.blocks[sel_.block].name + "':";
  if (vx_) s += " vx: " + vx_->describe();
  if (vy_) s += " vy: " + vy_->describe();
  if (spin_) s += " spin: " + spin_->describe();
  return s;
}

void VelocityCondition::setup(Model& m) {
  if (rigid_) {
    Block& b = m.blocks[sel_.block];
    if (vx_) b.prescribed |= Block::kDriveX;
    if (vy_) b.prescribed |= Block::kDriveY;
    if (spin_) b.prescribed |= Block::kDriveSpin;
    return;
  }
  for (int g : sel_.points) {
    m.gp[g].fixed_x = m.gp[g].fixed_x || vx_.has_value();
    m.gp[g].fixed_y = m.gp[g].fixed_y || vy_.has_value();
  }
}

void VelocityCondition::velocities(Model& m, double t) {
  if (rigid_) {
    Block& b = m.blocks[sel_.block];
    if (vx_) b.vc.x() = (*vx_)(t);
    if (vy_) b.vc.y() = (*vy_)(t);
    if (spin_) b.omega = (*spin_)(t);
    return;
  }
  for (int g : sel_.points) {
    if (vx_) m.gp[g].v.x() = (*vx_)(t);
    if (vy_) m.gp[g].v.y() = (*vy_)(t);
  }
}

double VelocityCondition::duration() const {
  double d = 0.0;
  for (const auto* f : {&vx_, &vy_, &spin_})
    if (f->has_value() && std::isfinite((*f)->duration())) d = std::max(d, (*f)->duration());
  return d;
}

namespace {

std::unique_ptr<BoundaryCondition> make_velocity(const ConditionInput& in) {
  const auto vx = in.function("vx"), vy = in.function("vy"), spin = in.function("spin");
  if (!vx && !vy && !spin) throw InputError(in.where + ": a velocity condition needs vx, vy or spin");
  if (spin && !in.rigid) throw InputError(in.value("spin")->where + ": spin applies to rigid blocks only");
  return std::make_unique<VelocityCondition>(in.selection, in.rigid, vx, vy, spin);
}

using Type = ConditionKey::Type;

// The rank places the kind in messages' list: fixed, velocity, traction, quiet.
const ConditionKindRegistrar velocity_kind{20, ConditionKind{
    "velocity", "prescribed velocity components, functions of stage time",
    {{"vx", Type::time_function, Dimension::velocity, "x velocity history"},
     {"vy", Type::time_function, Dimension::velocity, "y velocity history"},
     {"spin", Type::time_function, Dimension::angular_velocity, "angular velocity history (rigid blocks only)"}},
    true, make_velocity, {}}};

}  // namespace
}  // namespace rockdem
