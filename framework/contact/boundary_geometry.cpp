#include "framework/contact/boundary_geometry.hpp"

#include <algorithm>
#include <cmath>

#include "framework/core/threads.hpp"

namespace rockdem {
namespace {

// Tangent length t and radius r of the rounding at a vertex where the unit boundary direction turns
// from e1 to e2 (left turns are convex on a counter-clockwise loop), with rounding length d and
// adjacent edge lengths l1, l2; tan(th/2) = sin th / (1 + cos th). Only real corners are rounded:
// a boundary gridpoint of a deformable block on a straight face turns by a tiny angle, and
// rounding it would bend the normal of points that merely pass over it.
constexpr double kSin5 = 0.08715574274765817;  // sin(5 degrees)

void corner_rounding(const Vec2& e1, const Vec2& e2, double l1, double l2, double d, double& t, double& r) {
  t = r = 0.0;
  const double sn = cross(e1, e2), cs = e1.dot(e2);
  if (d <= 0.0 || sn <= 0.0 || (cs > 0.0 && sn < kSin5)) return;
  const double h = sn / (1.0 + cs);
  t = std::min({d * h, 0.5 * l1, 0.5 * l2});
  r = t / h;
}

}  // namespace

void BoundaryGeometry::update(const Model& m, double rounding, int threads) {
  const std::size_t nb = m.blocks.size();
  first_.resize(nb + 1);
  std::size_t total = 0;
  for (std::size_t b = 0; b < nb; ++b) {
    first_[b] = total;
    total += m.blocks[b].boundary.size();
  }
  first_[nb] = total;
  edges_.resize(total);
  const double cos5 = std::cos(5.0 * M_PI / 180.0);
  threaded_for(threads, 0, static_cast<std::ptrdiff_t>(nb), [&](std::ptrdiff_t bi) {
    const auto b = static_cast<std::size_t>(bi);
    if (!m.part.current(static_cast<int>(b))) return;
    const std::vector<int>& loop = m.blocks[b].boundary;
    const int n = static_cast<int>(loop.size());
    BoundaryEdge* e = edges_.data() + first_[b];
    for (int k = 0; k < n; ++k) {
      const Vec2& a = m.gp[loop[static_cast<std::size_t>(k)]].x;
      const Vec2& c = m.gp[loop[static_cast<std::size_t>(k + 1 == n ? 0 : k + 1)]].x;
      const Vec2 d = c - a;
      e[k].lo = a.cwiseMin(c);
      e[k].hi = a.cwiseMax(c);
      e[k].len = d.norm();
      e[k].u = d / e[k].len;
      e[k].nrm = Vec2(e[k].u.y(), -e[k].u.x());
    }
    for (int k = 0; k < n; ++k) {
      const BoundaryEdge& in = e[(k - 1 + n) % n];
      BoundaryEdge& out = e[k];
      corner_rounding(in.u, out.u, in.len, out.len, rounding, out.t, out.r);
      out.flat = in.u.dot(out.u) >= cos5;
      if (out.flat) out.flat_normal = Vec2(in.u.y() + out.u.y(), -(in.u.x() + out.u.x())).normalized();
    }
  });
}

BoundaryGeometry& boundary_geometry() {
  thread_local BoundaryGeometry g;
  return g;
}

}  // namespace rockdem
