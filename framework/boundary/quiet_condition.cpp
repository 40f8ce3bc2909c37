#include "framework/boundary/quiet_condition.hpp"

#include <cmath>
#include <sstream>

#include "framework/boundary/condition_kinds.hpp"
#include "framework/core/error.hpp"
#include "framework/plugin_api/rock_material.hpp"

namespace rockdem {

QuietCondition::QuietCondition(FaceSelection sel, double rho, double cp, double cs)
    : sel_(std::move(sel)), rho_(rho), cp_(cp), cs_(cs) {}

std::string QuietCondition::describe(const Model& m) const {
  std::ostringstream os;
  os << "quiet boundary on block '" << m.blocks[sel_.block].name << "': rho*Cp = " << rho_ * cp_ << ", rho*Cs = " << rho_ * cs_;
  return os.str();
}

double QuietCondition::forces(Model& m, double) {
  double applied = 0.0;
  for_each_edge(m, sel_, [&](int ga, int gb, const Vec2& d) {
    const double len = d.norm();
    const Vec2 t = d / len;
    const Vec2 nrm(t.y(), -t.x());
    for (int g : {ga, gb}) {
      const Vec2& v = m.gp[g].v;
      const Vec2 f = -rho_ * (cp_ * v.dot(nrm) * nrm + cs_ * v.dot(t) * t) * 0.5 * len;
      m.gp[g].f += f;
      applied += f.norm();
    }
  });
  return applied;
}

namespace {

std::unique_ptr<BoundaryCondition> make_quiet(const ConditionInput& in) {
  if (in.rigid) throw InputError(in.where + ": quiet boundaries act on deformable blocks");
  const Model& m = in.model;
  const auto zone = static_cast<std::size_t>(m.blocks[in.selection.block].first_zone);
  const auto& mat = *m.materials[static_cast<std::size_t>(m.zones[zone].material)];
  const double rho = mat.density(), k = mat.bulk_modulus(), g = mat.shear_modulus();
  return std::make_unique<QuietCondition>(in.selection, rho, std::sqrt((k + 4.0 * g / 3.0) / rho), std::sqrt(g / rho));
}

// The rank places the kind in messages' list: fixed, velocity, traction, quiet.
const ConditionKindRegistrar quiet_kind{40, ConditionKind{
    "quiet", "viscous boundary absorbing outgoing waves (deformable blocks)", {}, false, make_quiet}};

}  // namespace
}  // namespace rockdem
