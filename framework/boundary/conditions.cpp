#include "framework/boundary/conditions.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "framework/core/error.hpp"

namespace rockdem {

bool BoundaryCondition::active_in(const std::string& stage) const {
  return stages.empty() || std::find(stages.begin(), stages.end(), stage) != stages.end();
}

Vec2 face_direction(const std::string& name, const std::string& where) {
  if (name == "top") return {0, 1};
  if (name == "bottom") return {0, -1};
  if (name == "left") return {-1, 0};
  if (name == "right") return {1, 0};
  if (name == "all") return {0, 0};
  throw InputError(where + ": unknown face '" + name + "'; valid faces: top, bottom, left, right, all");
}

FaceSelection select_face(const Model& m, int block, const Vec2& dir) {
  FaceSelection sel;
  sel.block = block;
  const Block& b = m.blocks[block];
  const int n = static_cast<int>(b.boundary.size());
  const double cos10 = std::cos(10.0 * M_PI / 180.0);
  for (int i = 0; i < n; ++i) {
    const Vec2 d = m.gp[b.boundary[(i + 1) % n]].x - m.gp[b.boundary[i]].x;
    const Vec2 out = Vec2(d.y(), -d.x()).normalized();
    if (dir.squaredNorm() == 0.0 || out.dot(dir) > cos10) {
      sel.edges.push_back(i);
      sel.points.push_back(b.boundary[i]);
      sel.points.push_back(b.boundary[(i + 1) % n]);
    }
  }
  std::sort(sel.points.begin(), sel.points.end());
  sel.points.erase(std::unique(sel.points.begin(), sel.points.end()), sel.points.end());
  return sel;
}

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

TractionCondition::TractionCondition(FaceSelection sel, TimeFunction normal, TimeFunction shear)
    : sel_(std::move(sel)), normal_(std::move(normal)), shear_(std::move(shear)) {}

std::string TractionCondition::describe(const Model& m) const {
  return "traction on block '" + m.blocks[sel_.block].name + "': normal " + normal_.describe() + ", shear " +
         shear_.describe();
}

double TractionCondition::forces(Model& m, double t) {
  double applied = 0.0;
  const Block& b = m.blocks[sel_.block];
  const int n = static_cast<int>(b.boundary.size());
  const double sn = normal_(t), ss = shear_(t);
  for (int i : sel_.edges) {
    const int ga = b.boundary[i], gb = b.boundary[(i + 1) % n];
    const Vec2 d = m.gp[gb].x - m.gp[ga].x;  // counter-clockwise tangent times length
    const Vec2 out(d.y(), -d.x());            // outward normal times length
    const Vec2 f = -sn * out + ss * d;        // compression pushes inward
    m.gp[ga].f += 0.5 * f;
    m.gp[gb].f += 0.5 * f;
    applied += f.norm();
  }
  return applied;
}

QuietCondition::QuietCondition(FaceSelection sel, double rho, double cp, double cs)
    : sel_(std::move(sel)), rho_(rho), cp_(cp), cs_(cs) {}

std::string QuietCondition::describe(const Model& m) const {
  std::ostringstream os;
  os << "quiet boundary on block '" << m.blocks[sel_.block].name << "': rho*Cp = " << rho_ * cp_ << ", rho*Cs = " << rho_ * cs_;
  return os.str();
}

double QuietCondition::forces(Model& m, double) {
  double applied = 0.0;
  const Block& b = m.blocks[sel_.block];
  const int n = static_cast<int>(b.boundary.size());
  for (int i : sel_.edges) {
    const int ga = b.boundary[i], gb = b.boundary[(i + 1) % n];
    const Vec2 d = m.gp[gb].x - m.gp[ga].x;
    const double len = d.norm();
    const Vec2 t = d / len;
    const Vec2 nrm(t.y(), -t.x());
    for (int g : {ga, gb}) {
      const Vec2& v = m.gp[g].v;
      const Vec2 f = -rho_ * (cp_ * v.dot(nrm) * nrm + cs_ * v.dot(t) * t) * 0.5 * len;
      m.gp[g].f += f;
      applied += f.norm();
    }
  }
  return applied;
}

}  // namespace rockdem
