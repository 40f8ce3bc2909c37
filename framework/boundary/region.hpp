#pragma once
// Boundary gridpoints selected by where they are rather than by block and face: all boundary
// gridpoints inside a box, or within a tolerance of a line segment, across any number of blocks
// (rollers on the sides of a rock mass, a fixed base), one FaceSelection per block reached.
#include <array>
#include <limits>
#include <optional>
#include <vector>

#include "framework/boundary/conditions.hpp"

namespace rockdem {

struct Region {
  // A box [x0, x1] x [y0, y1], or a segment from -> to with a tolerance [m].
  std::optional<std::array<double, 4>> box;  // x0, y0, x1, y1
  Vec2 from = Vec2::Zero(), to = Vec2::Zero();
  double tolerance = 0.0;
  bool contains(const Vec2& x) const;
};

// For each block with boundary gridpoints in the region: those gridpoints (at their initial
// positions) and the boundary edges whose two ends are both in it; blocks in block order.
std::vector<FaceSelection> select_region(const Model& m, const Region& r);

// The boundary edges of a block that face `direction` (within 10 degrees, as select_face) AND lie
// on the block's outer support line in that direction (both ends within `tolerance` of the
// block's extreme extent along it), so that the wall of a hole or the inside of a notch whose
// normal happens to point the same way is never selected. "all" (a zero direction) selects every
// boundary edge.
FaceSelection select_outer_face(const Model& m, int block, const Vec2& direction, double tolerance);

// The tolerance select_outer_face uses for a block when none is given: 1e-6 of the block's size.
double outer_face_tolerance(const Model& m, int block);

}  // namespace rockdem
