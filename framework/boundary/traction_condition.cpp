#include "framework/boundary/traction_condition.hpp"

#include "framework/boundary/condition_kinds.hpp"
#include "framework/core/error.hpp"

namespace rockdem {

TractionCondition::TractionCondition(FaceSelection sel, TimeFunction normal, TimeFunction shear)
    : sel_(std::move(sel)), normal_(std::move(normal)), shear_(std::move(shear)) {}

std::string TractionCondition::describe(const Model& m) const {
  return "traction on block '" + m.blocks[sel_.block].name + "': normal " + normal_.describe() + ", shear " +
         shear_.describe();
}

double TractionCondition::forces(Model& m, double t) {
  double applied = 0.0;
  const double sn = normal_(t), ss = shear_(t);
  for_each_edge(m, sel_, [&](int ga, int gb, const Vec2& d) {  // d: counter-clockwise tangent times length
    const Vec2 out(d.y(), -d.x());                              // outward normal times length
    const Vec2 f = -sn * out + ss * d;                          // compression pushes inward
    m.gp[ga].f += 0.5 * f;
    m.gp[gb].f += 0.5 * f;
    applied += f.norm();
  });
  return applied;
}

namespace {

std::unique_ptr<BoundaryCondition> make_traction(const ConditionInput& in) {
  // A stress not given is zero.
  const auto sn = in.function("normal"), ss = in.function("shear");
  return std::make_unique<TractionCondition>(in.selection, sn ? *sn : TimeFunction::constant(0.0),
                                             ss ? *ss : TimeFunction::constant(0.0));
}

using Type = ConditionKey::Type;

// The rank places the kind in messages' list: fixed, velocity, traction, quiet.
const ConditionKindRegistrar traction_kind{30, ConditionKind{
    "traction", "normal and shear stress on a face, functions of stage time",
    {{"normal", Type::time_function, Dimension::stress, "normal stress history, compression positive (default 0)"},
     {"shear", Type::time_function, Dimension::stress, "shear stress history, counter-clockwise positive (default 0)"}},
    false, make_traction, {}}};

}  // namespace
}  // namespace rockdem
