#pragma once
// Each block's boundary as the narrow phase and the per-step contact geometry read it: per edge its
// unit direction, length and outward normal, per vertex its corner rounding and whether it is a
// real corner. Built once per call of detect_contacts and update_contact_geometry for the blocks
// whose positions are current on this process, so that a point tested against an edge reads the
// edge instead of recomputing it: before, every point against every edge of the other block took
// a square root and a division, and every rounded projection five square roots and two corner
// roundings (issue 13, docs/performance.md). The values are those expressions computed once, in
// the same order, so contacts come out bit for bit as before.
#include <vector>

#include "framework/model/model.hpp"

namespace rockdem {

// Boundary position k of a block: the edge from boundary[k] to boundary[k + 1] and the vertex
// boundary[k] (between edges k - 1 and k).
struct BoundaryEdge {
  Vec2 u = Vec2::Zero();    // unit direction of edge k
  Vec2 nrm = Vec2::Zero();  // its outward normal (u turned clockwise: the loop is counter-clockwise)
  double len = 0.0;         // its length [m]
  Vec2 lo = Vec2::Zero(), hi = Vec2::Zero();  // its bounding box
  // Rounding of vertex k (tangent length t and radius r; both 0 where the vertex is not rounded:
  // concave, flat, or rounding 0).
  double t = 0.0, r = 0.0;
  // Vertex k is flat (its edges turn by less than about 5 degrees: a gridpoint in the middle of a
  // deformable block's face); it then has one side, with the mean normal of its two edges.
  bool flat = false;
  Vec2 flat_normal = Vec2::Zero();
};

class BoundaryGeometry {
 public:
  // Recompute the entries of every block whose state is current here (Partition::current) for
  // the gridpoint positions now and the given corner rounding length [m].
  void update(const Model& m, double rounding, int threads = 1);
  // Block position b's entries, indexed by boundary position.
  const BoundaryEdge* of(int b) const { return edges_.data() + first_[static_cast<std::size_t>(b)]; }

 private:
  std::vector<std::size_t> first_;
  std::vector<BoundaryEdge> edges_;
};

// The table of this thread, kept between calls (its storage reused).
BoundaryGeometry& boundary_geometry();

}  // namespace rockdem
