#pragma once
// Polygon utilities for block geometry: area, centroid, second moments, orientation, convexity,
// simplicity, point location and overlap between blocks. Polygons are open vertex lists (the last
// vertex is not repeated). Formulas for area, centroid and second moments are the shoelace/Green's
// theorem sums (e.g. Steger, "On the calculation of arbitrary moments of polygons", 1996).
#include <array>
#include <vector>

#include "framework/core/types.hpp"

namespace rockdem {

using Polygon = std::vector<Vec2>;

// Signed area: positive for a counter-clockwise polygon [m^2].
double signed_area(const Polygon& p);

// Area centroid. Requires a non-zero area.
Vec2 polygon_centroid(const Polygon& p);

// Second moments of area about the centroid, per unit density [m^4]:
// ixx = integral of (y - yc)^2, iyy = integral of (x - xc)^2, ixy = integral of (x - xc)(y - yc).
// Signs are those of a counter-clockwise polygon (ixx, iyy > 0) whatever the input orientation.
struct SecondMoments {
  double ixx = 0.0, iyy = 0.0, ixy = 0.0;
  double polar() const { return ixx + iyy; }  // rotational inertia per unit density
};
SecondMoments second_moments(const Polygon& p);

// Reverse the vertex order in place if the polygon is clockwise, keeping the first vertex first.
// Returns true if it reversed.
bool make_ccw(Polygon& p);

// Convex (every turn to the same side; collinear vertices allowed). Expects a simple polygon.
bool is_convex(const Polygon& p);

// Simple: at least 3 vertices, no two non-adjacent edges touch or cross, adjacent edges do not fold
// back on each other, no zero-length edge, and non-zero area. `tol` is a length.
bool is_simple(const Polygon& p, double tol = 0.0);

enum class PointLocation { outside, boundary, inside };
// Location of `q` relative to a simple polygon; within `tol` (a length) of an edge is `boundary`.
PointLocation locate_point(const Vec2& q, const Polygon& p, double tol = 0.0);

// Crossing-number test (half-open rule: an edge counts if it spans q.y in [ymin, ymax)) on a loop of
// n vertices given by `vertex(i)`, so that callers holding indices (block boundaries) need no copy.
template <class Vertex>
bool crossing_number_inside(const Vec2& q, std::size_t n, Vertex&& vertex) {
  bool inside = false;
  for (std::size_t i = 0, j = n - 1; i < n; j = i++) {
    const Vec2& a = vertex(i);
    const Vec2& b = vertex(j);
    if ((a.y() > q.y()) != (b.y() > q.y())) {
      const double x = a.x() + (q.y() - a.y()) * (b.x() - a.x()) / (b.y() - a.y());
      if (q.x() < x) inside = !inside;
    }
  }
  return inside;
}
inline bool point_in_polygon(const Vec2& q, const Polygon& p) {
  return locate_point(q, p, 0.0) == PointLocation::inside;
}

// Triangulation of a simple polygon by ear clipping (indices into p, counter-clockwise
// triangles). O(n^2), meant for block outlines, not for meshing (see mesh.hpp for zones).
std::vector<std::array<int, 3>> triangulate_polygon(const Polygon& p);

// Area of the intersection of two simple polygons (either orientation) [m^2]: both are split into
// triangles and the triangle pairs are clipped against each other (Sutherland & Hodgman 1974).
double intersection_area(const Polygon& a, const Polygon& b);

// True if two simple polygons share a region of positive area: the intersection area exceeds
// tol * (half the smaller perimeter), i.e. an overlap band thinner than `tol` (a length) is read
// as touching. Blocks touching along an edge or at a corner do not overlap.
bool polygons_overlap(const Polygon& a, const Polygon& b, double tol);

double perimeter(const Polygon& p);

}  // namespace rockdem
