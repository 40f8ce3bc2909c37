#include "framework/boundary/quiet_condition.hpp"

#include <cmath>
#include <sstream>

#include "framework/boundary/condition_kinds.hpp"
#include "framework/core/error.hpp"
#include "framework/plugin_api/rock_material.hpp"

namespace rockdem {

QuietCondition::QuietCondition(FaceSelection sel, double rho, double cp, double cs, Options o)
    : sel_(std::move(sel)), rho_(rho), cp_(cp), cs_(cs), o_(o) {}

std::string QuietCondition::describe(const Model& m) const {
  std::ostringstream os;
  os << (o_.seismic_input ? "compliant seismic base" : "quiet boundary") << " on block '" << m.blocks[sel_.block].name
     << "': rho*Cp = " << rho_ * cp_ << ", rho*Cs = " << rho_ * cs_ << " Pa s/m"
     << (o_.hold_static ? ", static reactions held" : "");
  for (const auto& sm : motions_)
    os << "; input '" << sm.motion->name << "' (" << seismic::motion_type_name(sm.motion->type) << ", "
       << (sm.motion->direction == 0 ? "x" : "y") << ", x" << sm.factor << ")";
  return os.str();
}

void QuietCondition::deactivated() {
  held_ = false;
  hold_.clear();
  hold_force_ = Vec2::Zero();
  hold_moment_ = 0.0;
}

void QuietCondition::setup(Model& m) {
  if (!o_.hold_static || held_) return;
  held_ = true;
  // The forces of the last step of the previous stage are still in place: at fixed degrees of
  // freedom they are the reactions (their opposite holds the model), elsewhere they are the small
  // residual of an equilibrium. A first stage starts from zero forces, so nothing is held.
  if (o_.rigid) {
    const Block& b = m.blocks[sel_.block];
    hold_force_ = -b.fc;
    hold_moment_ = -b.moment;
    m.blocks[sel_.block].fc = Vec2::Zero();
    m.blocks[sel_.block].moment = 0.0;
    return;
  }
  // A force held here is taken away from the gridpoint, so that another condition on the same
  // gridpoint (a model's corner: the seismic base and a free-field side) does not hold it again.
  hold_.resize(sel_.points.size());
  for (std::size_t k = 0; k < sel_.points.size(); ++k) {
    hold_[k] = -m.gp[sel_.points[k]].f;
    m.gp[sel_.points[k]].f.setZero();
  }
}

void QuietCondition::set_motions(const std::vector<StageMotion>& motions) {
  if (!o_.seismic_input) return;
  for (const auto& sm : motions)
    if (sm.motion->type == seismic::MotionType::within)
      throw InputError("motion '" + sm.motion->name + "' is a within record (incident and reflected waves), which a "
                       "compliant base cannot take: use base = \"rigid\" for it, or give the outcrop or incident motion");
  motions_ = motions;
}

Vec2 base_input(const std::vector<BoundaryCondition::StageMotion>& motions, double t, bool rigid_base) {
  Vec2 w = Vec2::Zero();
  for (const auto& sm : motions) {
    const double k = rigid_base || sm.motion->type == seismic::MotionType::outcrop ? 1.0 : 2.0;
    w[sm.motion->direction] += k * sm.factor * sm.motion->velocity(t);
  }
  return w;
}

double motions_duration(const std::vector<BoundaryCondition::StageMotion>& motions) {
  double d = 0.0;
  for (const auto& sm : motions) d = std::max(d, sm.motion->duration());
  return d;
}

double QuietCondition::forces(Model& m, double t) {
  double applied = 0.0;
  const Vec2 w = o_.seismic_input ? base_input(motions_, t, false) : Vec2::Zero();
  for_each_edge(m, sel_, [&](int ga, int gb, const Vec2& d) {
    const double len = d.norm();
    const Vec2 tn = d / len;
    const Vec2 nrm(tn.y(), -tn.x());
    for (int g : {ga, gb}) {
      // Dashpots on the velocity relative to the input: rho C (w - v), normal and tangential parts.
      const Vec2 dv = w - m.gp[g].v;
      const Vec2 f = rho_ * (cp_ * dv.dot(nrm) * nrm + cs_ * dv.dot(tn) * tn) * 0.5 * len;
      m.gp[g].f += f;
      applied += f.norm();
    }
  });
  if (!held_ || !m.part.owns(sel_.block)) return applied;
  if (o_.rigid) {
    add_rigid_load(m, sel_.block, hold_force_, hold_moment_);
    return applied + hold_force_.norm();
  }
  for (std::size_t k = 0; k < sel_.points.size(); ++k) {
    m.gp[sel_.points[k]].f += hold_[k];
    applied += hold_[k].norm();
  }
  return applied;
}

void QuietCondition::add_dashpots(const Model& m, std::vector<double>& c) const {
  const double cmax = rho_ * std::max(cp_, cs_);
  const Block& b = m.blocks[static_cast<std::size_t>(sel_.block)];
  const auto n = b.boundary.size();
  for (int i : sel_.edges) {
    const int ga = b.boundary[static_cast<std::size_t>(i)], gb = b.boundary[(static_cast<std::size_t>(i) + 1) % n];
    const double half = 0.5 * (m.gp[static_cast<std::size_t>(gb)].x - m.gp[static_cast<std::size_t>(ga)].x).norm();
    c[static_cast<std::size_t>(ga)] += cmax * half;
    c[static_cast<std::size_t>(gb)] += cmax * half;
  }
}

double QuietCondition::history_duration() const { return o_.seismic_input ? motions_duration(motions_) : 0.0; }

std::vector<double> QuietCondition::saved_state() const {
  if (!held_) return {};
  std::vector<double> s{1.0, hold_force_.x(), hold_force_.y(), hold_moment_};
  for (const Vec2& h : hold_) s.insert(s.end(), {h.x(), h.y()});
  return s;
}

void QuietCondition::restore_state(const std::vector<double>& s) {
  if (s.empty()) return;
  if (s.size() != 4 + 2 * (o_.rigid ? 0 : sel_.points.size()))
    throw InputError("checkpoint: the held forces of a quiet boundary do not match its gridpoints");
  held_ = s[0] != 0.0;
  hold_force_ = Vec2(s[1], s[2]);
  hold_moment_ = s[3];
  hold_.clear();
  for (std::size_t k = 4; k + 1 < s.size(); k += 2) hold_.emplace_back(s[k], s[k + 1]);
}

void add_rigid_load(Model& m, int block, const Vec2& force, double moment) {
  const Block& b = m.blocks[static_cast<std::size_t>(block)];
  const auto n = static_cast<double>(b.n_gp);
  Vec2 mean = Vec2::Zero();
  for (int k = 0; k < b.n_gp; ++k) mean += m.gp[b.first_gp + k].x;
  mean /= n;
  double spread = 0.0;
  for (int k = 0; k < b.n_gp; ++k) spread += (m.gp[b.first_gp + k].x - mean).squaredNorm();
  // Uniform shares carry the force (and its moment about the centroid through the mean point);
  // a field perpendicular to the offsets from the mean point adds no force and the rest of the moment.
  const double rest = moment - cross(mean - b.xc, force);
  for (int k = 0; k < b.n_gp; ++k) {
    GridPoint& g = m.gp[b.first_gp + k];
    g.f += force / n + (spread > 0.0 ? rest / spread : 0.0) * perp(g.x - mean);
  }
}

WaveImpedance face_impedance(const ConditionInput& in) {
  const Model& m = in.model;
  WaveImpedance z;
  if (!in.rigid) {
    const auto zone = static_cast<std::size_t>(m.blocks[in.selection.block].first_zone);
    const auto& mat = *m.materials[static_cast<std::size_t>(m.zones[zone].material)];
    const double k = mat.bulk_modulus(), g = mat.shear_modulus();
    z.rho = mat.density();
    z.cp = std::sqrt((k + 4.0 * g / 3.0) / z.rho);
    z.cs = std::sqrt(g / z.rho);
  }
  // Rigid blocks have a density but no elastic constants: the rock's wave speeds are given (and
  // may be given on deformable blocks too, e.g. for the far-field rock behind a stiffer lining).
  const auto cp = in.function("cp"), cs = in.function("cs"), rho = in.function("density");
  if (in.rigid && (!cp || !cs))
    throw InputError(in.where + ": block '" + m.blocks[in.selection.block].name +
                     "' is rigid, which has no elastic wave speeds: give the rock's cp and cs (e.g. cp = \"5000 m/s\", "
                     "cs = \"3000 m/s\"), and density if not the block's");
  if (cp) z.cp = (*cp)(0.0);
  if (cs) z.cs = (*cs)(0.0);
  if (rho) z.rho = (*rho)(0.0);
  else if (in.rigid) z.rho = m.blocks[in.selection.block].density;
  for (auto [v, key] : {std::pair{z.cp, "cp"}, std::pair{z.cs, "cs"}, std::pair{z.rho, "density"}})
    if (!(v > 0.0) || !std::isfinite(v))
      throw InputError((in.value(key) ? in.value(key)->where : in.where) + ": " + key + " must be positive and finite");
  return z;
}

namespace {

std::unique_ptr<BoundaryCondition> make_quiet(const ConditionInput& in) {
  const WaveImpedance z = face_impedance(in);
  return std::make_unique<QuietCondition>(in.selection, z.rho, z.cp, z.cs,
                                          QuietCondition::Options{false, hold_static_reactions(in), in.rigid});
}

}  // namespace

// Keys shared by the kinds that put dashpots on a face (quiet, seismic, free_field).
std::vector<ConditionKey> dashpot_keys() {
  using Type = ConditionKey::Type;
  return {{"cp", Type::time_function, Dimension::velocity, "P-wave speed of the rock behind the face (rigid blocks; default the zones')"},
          {"cs", Type::time_function, Dimension::velocity, "S-wave speed of the rock behind the face (rigid blocks; default the zones')"},
          {"density", Type::time_function, Dimension::density, "density of the rock behind the face (default the block's)"},
          {"static_reactions", Type::choice, Dimension::dimensionless,
           "hold (default): the forces the boundary carried when fixed stay applied; release: dashpots only"}};
}

bool hold_static_reactions(const ConditionInput& in) {
  const ConditionValue* v = in.value("static_reactions");
  if (!v) return true;
  const std::string& s = v->names.front();
  if (s != "hold" && s != "release")
    throw InputError(v->where + ": unknown static_reactions '" + s + "'; valid: hold (the forces a fixed boundary carried "
                     "at the end of the previous stage stay applied), release (dashpots only)");
  return s == "hold";
}

namespace {
// The rank places the kind in messages' list: fixed, velocity, traction, quiet.
const ConditionKindRegistrar quiet_kind{40, ConditionKind{
    "quiet", "viscous boundary absorbing outgoing waves (deformable and rigid blocks)", dashpot_keys(), false, make_quiet, {}}};
}  // namespace

}  // namespace rockdem
