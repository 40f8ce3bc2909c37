#include "framework/boundary/condition_kinds.hpp"

#include <algorithm>
#include <cmath>

#include "framework/core/error.hpp"
#include "framework/core/names.hpp"
#include "framework/plugin_api/rock_material.hpp"

namespace rockdem {

const ConditionValue* ConditionInput::value(const std::string& key) const {
  auto it = values.find(key);
  return it == values.end() ? nullptr : &it->second;
}

std::optional<TimeFunction> ConditionInput::function(const std::string& key) const {
  const ConditionValue* v = value(key);
  return v ? v->function : std::nullopt;
}

ConditionKinds& ConditionKinds::instance() {
  static ConditionKinds kinds;
  return kinds;
}

void ConditionKinds::add(int rank, ConditionKind kind) {
  const auto at = std::upper_bound(ranks_.begin(), ranks_.end(), rank);
  kinds_.insert(kinds_.begin() + (at - ranks_.begin()), std::move(kind));
  ranks_.insert(at, rank);
}

const ConditionKind* ConditionKinds::find(const std::string& name) const {
  for (const auto& k : kinds_)
    if (k.name == name) return &k;
  return nullptr;
}

const ConditionKind& ConditionKinds::get(const std::string& name, const std::string& where) const {
  if (const ConditionKind* k = find(name)) return *k;
  throw InputError(where + ": unknown boundary type '" + name + "'; valid: " + join_names(kinds_, &ConditionKind::name));
}

const ConditionKey* ConditionKinds::key(const std::string& name) const {
  for (const auto& k : kinds_)
    for (const auto& key : k.keys)
      if (key.name == name) return &key;
  return nullptr;
}

std::vector<std::string> ConditionKinds::key_names() const {
  std::vector<std::string> out;
  for (const auto& k : kinds_)
    for (const auto& key : k.keys)
      if (std::find(out.begin(), out.end(), key.name) == out.end()) out.push_back(key.name);
  return out;
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
    return std::make_unique<VelocityCondition>(in.selection, true,
                                               fx ? std::optional(TimeFunction::constant(0.0)) : std::nullopt,
                                               fy ? std::optional(TimeFunction::constant(0.0)) : std::nullopt, std::nullopt);
  }
  return std::make_unique<FixedCondition>(in.selection, fx, fy, in.rigid);
}

std::unique_ptr<BoundaryCondition> make_velocity(const ConditionInput& in) {
  const auto vx = in.function("vx"), vy = in.function("vy"), spin = in.function("spin");
  if (!vx && !vy && !spin) throw InputError(in.where + ": a velocity condition needs vx, vy or spin");
  if (spin && !in.rigid) throw InputError(in.value("spin")->where + ": spin applies to rigid blocks only");
  return std::make_unique<VelocityCondition>(in.selection, in.rigid, vx, vy, spin);
}

std::unique_ptr<BoundaryCondition> make_traction(const ConditionInput& in) {
  // A stress not given is zero.
  const auto sn = in.function("normal"), ss = in.function("shear");
  return std::make_unique<TractionCondition>(in.selection, sn ? *sn : TimeFunction::constant(0.0),
                                             ss ? *ss : TimeFunction::constant(0.0));
}

std::unique_ptr<BoundaryCondition> make_quiet(const ConditionInput& in) {
  if (in.rigid) throw InputError(in.where + ": quiet boundaries act on deformable blocks");
  const Model& m = in.model;
  const auto zone = static_cast<std::size_t>(m.blocks[in.selection.block].first_zone);
  const auto& mat = *m.materials[static_cast<std::size_t>(m.zones[zone].material)];
  const double rho = mat.density(), k = mat.bulk_modulus(), g = mat.shear_modulus();
  return std::make_unique<QuietCondition>(in.selection, rho, std::sqrt((k + 4.0 * g / 3.0) / rho), std::sqrt(g / rho));
}

using Type = ConditionKey::Type;

// The ranks give the order messages list the kinds and their keys in.
const ConditionKindRegistrar fixed_kind{10, ConditionKind{
    "fixed", "gridpoints (or a whole rigid block) held in place",
    {{"components", Type::names, Dimension::dimensionless, "components held, [\"x\"], [\"y\"] or both (default)"}},
    true, make_fixed}};
const ConditionKindRegistrar velocity_kind{20, ConditionKind{
    "velocity", "prescribed velocity components, functions of stage time",
    {{"vx", Type::time_function, Dimension::velocity, "x velocity history"},
     {"vy", Type::time_function, Dimension::velocity, "y velocity history"},
     {"spin", Type::time_function, Dimension::angular_velocity, "angular velocity history (rigid blocks only)"}},
    true, make_velocity}};
const ConditionKindRegistrar traction_kind{30, ConditionKind{
    "traction", "normal and shear stress on a face, functions of stage time",
    {{"normal", Type::time_function, Dimension::stress, "normal stress history, compression positive (default 0)"},
     {"shear", Type::time_function, Dimension::stress, "shear stress history, counter-clockwise positive (default 0)"}},
    false, make_traction}};
const ConditionKindRegistrar quiet_kind{40, ConditionKind{
    "quiet", "viscous boundary absorbing outgoing waves (deformable blocks)", {}, false, make_quiet}};

}  // namespace
}  // namespace rockdem
