#include "framework/boundary/seismic_condition.hpp"

#include <sstream>

#include "framework/boundary/condition_kinds.hpp"
#include "framework/boundary/quiet_condition.hpp"
#include "framework/core/error.hpp"

namespace rockdem {

std::string RigidBaseCondition::describe(const Model& m) const {
  std::ostringstream os;
  os << "rigid seismic base on block '" << m.blocks[sel_.block].name << "'";
  for (const auto& sm : motions_) {
    os << "; input '" << sm.motion->name << "' (" << (sm.motion->direction == 0 ? "x" : "y") << ", x" << sm.factor << ")";
    if (sm.motion->type == seismic::MotionType::outcrop)
      os << " [an outcrop record applied as the base motion: a rigid base reflects the waves that come down]";
  }
  return os.str();
}

void RigidBaseCondition::setup(Model& m) {
  if (rigid_) {
    m.blocks[sel_.block].prescribed |= Block::kDriveAll;
    return;
  }
  for (int g : sel_.points) m.gp[g].fixed_x = m.gp[g].fixed_y = true;
}

void RigidBaseCondition::velocities(Model& m, double t) {
  const Vec2 v = base_input(motions_, t, true);
  if (rigid_) {
    Block& b = m.blocks[sel_.block];
    b.vc = v;
    b.omega = 0.0;
    return;
  }
  for (int g : sel_.points) m.gp[g].v = v;
}

double RigidBaseCondition::history_duration() const { return motions_duration(motions_); }

namespace {

std::unique_ptr<BoundaryCondition> make_seismic(const ConditionInput& in) {
  std::string base = "compliant";
  if (const ConditionValue* v = in.value("base")) base = v->names.front();
  if (base == "rigid") {
    for (const char* k : {"cp", "cs", "density", "static_reactions"})
      if (const ConditionValue* v = in.value(k))
        throw InputError(v->where + ": '" + k + "' is for a compliant base (dashpots); a rigid base prescribes the motion");
    return std::make_unique<RigidBaseCondition>(in.selection, in.rigid);
  }
  if (base != "compliant")
    throw InputError(in.value("base")->where + ": unknown base '" + base +
                     "'; valid: compliant (quiet boundary with stress input, for outcrop or incident records), "
                     "rigid (prescribed velocity, for within records)");
  const WaveImpedance z = face_impedance(in);
  return std::make_unique<QuietCondition>(in.selection, z.rho, z.cp, z.cs,
                                          QuietCondition::Options{true, hold_static_reactions(in), in.rigid});
}

std::vector<ConditionKey> seismic_keys() {
  std::vector<ConditionKey> k{{"base", ConditionKey::Type::choice, Dimension::dimensionless,
                               "compliant (default: dashpots with the stress input 2 rho C v_incident) or rigid "
                               "(the motion's velocity prescribed)"}};
  for (auto& d : dashpot_keys()) k.push_back(std::move(d));
  return k;
}

const ConditionKindRegistrar seismic_kind{50, ConditionKind{
    "seismic", "where the stage's ground motions ([[motions]], stage key motion) enter: a compliant or rigid base",
    seismic_keys(), false, make_seismic, {}}};

}  // namespace
}  // namespace rockdem
