#include "framework/boundary/conditions.hpp"

#include <algorithm>
#include <cmath>

#include "framework/core/error.hpp"

namespace rockdem {

bool BoundaryCondition::active_in(const std::string& stage) const {
  if (removed) return false;
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

bool renumber(FaceSelection& sel, const Renumbering& r) {
  sel.block = r.block[static_cast<std::size_t>(sel.block)];
  return r.points(sel.points) && sel.block >= 0;
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

}  // namespace rockdem
