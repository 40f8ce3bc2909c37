// History quantities by location (`[[histories]] at = [x, y]`, and `to = [x, y]` for a joint
// segment): contact quantities of the contact nearest a point, or averaged (weighted by contact
// length) over the closed contacts along a segment; zone quantities of the zone containing a
// point. What is measured is looked up at every sample, so it follows contacts that come and go,
// and the model's renumbering after an excavation.
#include <cmath>
#include <limits>

#include "framework/geometry/polygon.hpp"
#include "framework/mechanics/engine.hpp"
#include "framework/mechanics/history_quantities.hpp"
#include "framework/mechanics/rigid_chord.hpp"

namespace rockdem {
namespace {

double contact_value(const Contact& c, int component, int kind) {
  const JointResponse& r = c.response;
  switch (kind) {
    case 0: return component == 0 ? r.sigma_n : r.tau;                                  // stress
    case 1: return component == 0 ? r.u_n : r.u_s;                                      // displacement
    default: return component == 0 ? (r.slipping ? 1.0 : 0.0) : component == 1 ? (r.open ? 1.0 : 0.0) : r.dilation;
  }
}

// The contact nearest `at`, or the length-weighted mean over the contacts within the detection
// band of the segment at..to; NaN where there is none.
double contact_quantity(const Model& m, const HistoryTarget& t, int kind) {
  if (!t.segment) {
    const Contact* best = nullptr;
    double d2 = std::numeric_limits<double>::infinity();
    for (const Contact& c : m.contacts.items) {
      const double d = (m.gp[c.point].x - t.at).squaredNorm();
      if (d < d2) d2 = d, best = &c;
    }
    return best ? contact_value(*best, t.component, kind) : std::nan("");
  }
  const Vec2 d = t.to - t.at;
  const double l2 = d.squaredNorm();
  const double band = 2.0 * (m.contacts.rounding + m.contacts.tolerance);
  double sum = 0.0, weight = 0.0;
  for (const Contact& c : m.contacts.items) {
    if (c.response.open) continue;
    const Vec2 x = m.gp[c.point].x;
    const double s = l2 > 0.0 ? (x - t.at).dot(d) / l2 : 0.0;
    if (s < 0.0 || s > 1.0 || (x - (t.at + s * d)).norm() > band) continue;
    sum += c.length * contact_value(c, t.component, kind);
    weight += c.length;
  }
  return weight > 0.0 ? sum / weight : std::nan("");
}

// The zone that contained `at` at the start (the material point there, as gridpoint histories
// follow a gridpoint) and the point's barycentric coordinates in it.
const Zone* zone_at(const Model& m, const Vec2& at, std::array<double, 3>& w) {
  for (const Zone& z : m.zones) {
    const Vec2 a = m.gp[z.n[0]].x0, b = m.gp[z.n[1]].x0, c = m.gp[z.n[2]].x0;
    const double area = cross(b - a, c - a);
    if (area == 0.0) continue;
    w = {cross(b - at, c - at) / area, cross(c - at, a - at) / area, cross(a - at, b - at) / area};
    const double tol = -1e-12;
    if (w[0] >= tol && w[1] >= tol && w[2] >= tol) return &z;
  }
  return nullptr;
}

double zone_stress(const Model& m, const Engine&, const HistoryTarget& t) {
  std::array<double, 3> w{};
  const Zone* z = zone_at(m, t.at, w);
  if (!z) return std::nan("");
  const Voigt3& s = z->stress;
  if (t.component < 3) return s[t.component];
  const double c = 0.5 * (s[0] + s[1]), r = std::hypot(0.5 * (s[0] - s[1]), s[2]);
  return t.component == 3 ? c + r : c - r;  // s1 (algebraically largest), s2
}

// The rigid block whose initial outline contains `p`, or null.
const Block* rigid_block_at(const Model& m, const Vec2& p) {
  for (const Block& b : m.blocks)
    if (b.rigid && crossing_number_inside(p, b.boundary.size(), [&](std::size_t i) -> const Vec2& { return m.gp[b.boundary[i]].x0; }))
      return &b;
  return nullptr;
}

// The displacement (or velocity) of the material point that started at `at`: interpolated in the
// zone containing it, or that of the rigid block's point.
double motion_at(const Model& m, const Engine& e, const HistoryTarget& t, bool velocity) {
  std::array<double, 3> w{};
  const Zone* z = zone_at(m, t.at, w);
  if (!z) {
    const Block* b = rigid_block_at(m, t.at);
    if (!b) return std::nan("");
    const Vec2 r0 = t.at - b->xc0;
    const double c = std::cos(b->theta), s = std::sin(b->theta);
    const Vec2 r(c * r0.x() - s * r0.y(), s * r0.x() + c * r0.y());
    // The velocity the engine gives the block's gridpoints: the chord of the last step, over the
    // step that moved them (the refresh ending a step may have changed dt() since).
    const Vec2 u = velocity ? RigidChord(b->omega, e.moved_dt()).velocity(b->vc, r) : Vec2(b->xc - b->xc0 + r - r0);
    return u[t.component];
  }
  double u = 0.0;
  for (int k = 0; k < 3; ++k) {
    const GridPoint& g = m.gp[z->n[k]];
    u += w[k] * (velocity ? g.v : Vec2(g.x - g.x0))[t.component];
  }
  return u;
}

double displacement_at(const Model& m, const Engine& e, const HistoryTarget& t) { return motion_at(m, e, t, false); }
double velocity_at(const Model& m, const Engine& e, const HistoryTarget& t) { return motion_at(m, e, t, true); }

HistoryQuantity by_location(std::string name, std::string unit, std::string description, std::vector<std::string> comps,
                            std::function<double(const Model&, const Engine&, const HistoryTarget&)> f, bool segment,
                            unsigned reads) {
  HistoryQuantity q{std::move(name), std::move(unit), std::move(description), false, false, false, std::move(comps),
                    Reduction::state, std::move(f)};
  q.state_parts = reads;
  q.needs_point = true;
  q.takes_segment = segment;
  return q;
}

const HistoryQuantityRegistrar contact_stress_q{by_location(
    "contact_stress", "Pa", "joint stress of the contact nearest `at` (or mean over the segment at..to), normal "
    "(compression positive) or shear", {"normal", "shear"},
    [](const Model& m, const Engine&, const HistoryTarget& t) { return contact_quantity(m, t, 0); }, true, kContactState)};
const HistoryQuantityRegistrar contact_displacement_q{by_location(
    "contact_displacement", "m", "joint displacement of the contact nearest `at` (or mean over the segment at..to): "
    "normal (opening positive) or shear (offset from the mated position)", {"normal", "shear"},
    [](const Model& m, const Engine&, const HistoryTarget& t) { return contact_quantity(m, t, 1); }, true, kContactState)};
const HistoryQuantityRegistrar contact_state_q{by_location(
    "contact_state", "", "state of the contact nearest `at` (or mean over the segment at..to): slipping (1/0), "
    "open (1/0) or dilation [m]", {"slip", "open", "dilation"},
    [](const Model& m, const Engine&, const HistoryTarget& t) { return contact_quantity(m, t, 2); }, true, kContactState)};
const HistoryQuantityRegistrar zone_stress_q{by_location(
    "zone_stress", "Pa", "stress of the zone containing `at` (tension positive): sxx, syy, sxy, or the principal "
    "stresses s1 >= s2", {"sxx", "syy", "sxy", "s1", "s2"}, zone_stress, false, kZoneState)};
const HistoryQuantityRegistrar displacement_at_q{by_location(
    "displacement_at", "m", "displacement of the material point that started at `at` (interpolated in the zone containing it, or of the rigid block containing it), x or y", {"x", "y"},
    displacement_at, false, 0)};
const HistoryQuantityRegistrar velocity_at_q{by_location(
    "velocity_at", "m/s", "velocity of the material point that started at `at` (interpolated in the zone containing it, or of the rigid block containing it, whose points move by their chord; the velocity of the last step), x or y", {"x", "y"},
    velocity_at, false, 0)};

}  // namespace
}  // namespace rockdem
