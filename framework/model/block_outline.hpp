#pragma once
// A block's outline as it is now: the positions of its boundary gridpoints, counter-clockwise
// (a geometry Polygon), for areas and centroids of blocks that move (drift results, scaling).
#include <vector>

#include "framework/model/model.hpp"

namespace rockdem {

inline std::vector<Vec2> block_outline(const Model& m, const Block& b) {
  std::vector<Vec2> p;
  p.reserve(b.boundary.size());
  for (int g : b.boundary) p.push_back(m.gp[static_cast<std::size_t>(g)].x);
  return p;
}

}  // namespace rockdem
