#include "framework/boundary/region.hpp"

#include <algorithm>
#include <cmath>

namespace rockdem {

bool Region::contains(const Vec2& x) const {
  if (box) {
    const auto& b = *box;
    return x.x() >= b[0] && x.x() <= b[2] && x.y() >= b[1] && x.y() <= b[3];
  }
  const Vec2 d = to - from;
  const double l2 = d.squaredNorm();
  const double s = l2 > 0.0 ? std::clamp((x - from).dot(d) / l2, 0.0, 1.0) : 0.0;
  return (x - (from + s * d)).norm() <= tolerance;
}

std::vector<FaceSelection> select_region(const Model& m, const Region& r) {
  std::vector<FaceSelection> out;
  for (std::size_t bi = 0; bi < m.blocks.size(); ++bi) {
    const Block& b = m.blocks[bi];
    const int n = static_cast<int>(b.boundary.size());
    FaceSelection sel;
    sel.block = static_cast<int>(bi);
    std::vector<char> in(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) in[static_cast<std::size_t>(i)] = r.contains(m.gp[b.boundary[i]].x0);
    for (int i = 0; i < n; ++i) {
      if (in[static_cast<std::size_t>(i)]) sel.points.push_back(b.boundary[i]);
      if (in[static_cast<std::size_t>(i)] && in[static_cast<std::size_t>((i + 1) % n)]) sel.edges.push_back(i);
    }
    if (sel.points.empty()) continue;
    std::sort(sel.points.begin(), sel.points.end());
    out.push_back(std::move(sel));
  }
  return out;
}

double outer_face_tolerance(const Model& m, int block) {
  const Block& b = m.blocks[block];
  Vec2 lo = m.gp[b.boundary.front()].x, hi = lo;
  for (int g : b.boundary) {
    lo = lo.cwiseMin(m.gp[g].x);
    hi = hi.cwiseMax(m.gp[g].x);
  }
  return 1e-6 * (hi - lo).norm();
}

FaceSelection select_outer_face(const Model& m, int block, const Vec2& dir, double tolerance) {
  FaceSelection all = select_face(m, block, dir);
  if (dir.squaredNorm() == 0.0) return all;
  const Block& b = m.blocks[block];
  const Vec2 u = dir.normalized();
  double extreme = -std::numeric_limits<double>::infinity();
  for (int g : b.boundary) extreme = std::max(extreme, m.gp[g].x.dot(u));
  const int n = static_cast<int>(b.boundary.size());
  auto on_line = [&](int g) { return m.gp[g].x.dot(u) >= extreme - tolerance; };
  FaceSelection sel;
  sel.block = block;
  for (int i : all.edges) {
    const int ga = b.boundary[i], gb = b.boundary[(i + 1) % n];
    if (!on_line(ga) || !on_line(gb)) continue;
    sel.edges.push_back(i);
    sel.points.push_back(ga);
    sel.points.push_back(gb);
  }
  std::sort(sel.points.begin(), sel.points.end());
  sel.points.erase(std::unique(sel.points.begin(), sel.points.end()), sel.points.end());
  return sel;
}

}  // namespace rockdem
