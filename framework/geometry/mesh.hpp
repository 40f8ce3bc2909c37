#pragma once
// Triangular zone meshes for deformable blocks. CGAL stays inside mesh.cpp (compile time).
#include <array>
#include <vector>

#include "framework/geometry/polygon.hpp"

namespace rockdem {

struct TriMesh {
  std::vector<Vec2> nodes;
  std::vector<std::array<int, 3>> triangles;  // node indices, counter-clockwise
  // Boundary nodes as a counter-clockwise loop starting at the polygon's first vertex. Nodes are
  // numbered boundary loop first (node i == boundary[i]), interior nodes after.
  std::vector<int> boundary;
  std::vector<int> corners;  // node index of each input polygon vertex, in polygon order
};

// Unstructured mesh of a simple polygon (either orientation; the mesh is counter-clockwise):
// each polygon edge is first split into equal segments no longer than zone_size (so boundary
// gridpoints are evenly spaced along each face), then CGAL's constrained Delaunay triangulation
// is refined (CGAL Mesh_2, Delaunay refinement after Ruppert and Shewchuk) towards zones with no
// angle under ~20.7 degrees (B = sin^2 = 0.125) and no edge longer than zone_size, without
// splitting the boundary further. Measured: minimum angles 26-36 degrees, longest edges up to
// ~1.3 zone_size. Should that refinement leave an angle under 20 degrees, the full refinement
// (which may split boundary edges) is used. Throws InputError for a non-simple polygon or
// zone_size <= 0.
TriMesh mesh_polygon(const Polygon& polygon, double zone_size);

// Structured mesh of the rectangle [x0, x0+w] x [y0, y0+h] with nx x ny cells, so that boundary
// gridpoints are evenly spaced. The boundary loop starts at (x0, y0), the rectangle's first vertex
// when written counter-clockwise from its lower-left corner.
enum class RectPattern {
  regular,      // every cell split along the same diagonal (anisotropic, stiffer one way)
  alternating,  // diagonals alternate in a checkerboard (symmetric "union jack")
  crossed,      // each cell split by both diagonals into four zones around a centre node
};
TriMesh mesh_rectangle(double x0, double y0, double w, double h, int nx, int ny,
                       RectPattern pattern = RectPattern::alternating);

struct MeshQuality {
  double min_angle_deg = 0.0;  // smallest interior angle of any zone
  double max_edge = 0.0, min_edge = 0.0;
  double area = 0.0;  // sum of zone areas
  double min_zone_area = 0.0;
};
MeshQuality mesh_quality(const TriMesh& m);

}  // namespace rockdem
