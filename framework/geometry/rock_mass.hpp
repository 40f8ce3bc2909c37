#pragma once
// Rock masses from joint sets: a domain polygon cut into blocks by joint sets (deterministic or a
// seeded stochastic DFN), named joints (faults), openings and regions. The cutting is done in
// CGAL's exact Arrangement_2 (exact predicates and constructions) inside rock_mass.cpp; only the
// finished blocks are converted to double. Input and output are plain data (no TOML), so code and
// the case reader (framework/io/rock_mass_reader.cpp) feed it alike. The rules (traces and rock
// bridges, faces with holes, sliver merging, edge labels, block order) are in
// docs/rock-mass-generator.md; the comments below state them briefly.
//
// Members named `where` are the places that messages name ("case.toml:12 [rock_mass.joint_sets]
// 'J1'"); every degenerate input is an InputError naming the `where` of the offending item.
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "framework/geometry/polygon.hpp"

namespace rockdem {

// A joint set. Each joint of the set is a straight line across the domain (or across `region`);
// along it, trace segments (the joint) alternate with gaps (rock bridges). Dip is the apparent dip
// in the section plane: the joint runs along (cos dip, -sin dip), so a positive dip descends
// towards +x. Joints are spaced `spacing` apart normal to the set, one of them through `origin`.
struct JointSetInput {
  std::string name;
  double dip = 0.0;                                         // [rad]
  double spacing = 0.0;                                     // normal spacing [m], > 0
  double trace = std::numeric_limits<double>::infinity();  // trace length [m]; infinite: persistent
  double gap = 0.0;                                         // rock-bridge length between traces [m]
  Vec2 origin = Vec2::Zero();                               // a point the set's first joint passes through
  // Standard deviations of the normal distributions the values are drawn from (0: deterministic).
  // Spacings, traces and gaps are drawn per joint / per segment and kept at least 10 % of their
  // mean; a dip is drawn per joint.
  double dip_sd = 0.0, spacing_sd = 0.0, trace_sd = 0.0, gap_sd = 0.0;
  std::optional<Polygon> region;  // the set exists only inside this polygon, whose outline is a glued cut
  std::string where;
};

// A single named joint (a fault) from a to b. Parts of it that end inside a block (dangling) do
// not cut; give its ends on or beyond the domain boundary for a through-going fault.
struct NamedJointInput {
  std::string name;
  Vec2 a = Vec2::Zero(), b = Vec2::Zero();
  std::string where;
};

// An opening, cut as its own block (joints inside it do not cut it).
struct OpeningInput {
  enum class Shape { circle, horseshoe, polygon };
  std::string name;
  Shape shape = Shape::circle;
  Vec2 centre = Vec2::Zero();  // circle: centre; horseshoe: middle of the floor
  double radius = 0.0;         // circle [m]
  int segments = 32;           // circle: number of sides; horseshoe: sides of the arch
  double width = 0.0, wall_height = 0.0, arch_rise = 0.0;  // horseshoe [m]; rise 0: width/2
  Polygon polygon;             // polygon openings
  std::string where;
};

// A region: the blocks inside it carry its name (their group), its zone size and, if not jointed,
// the region is one block that no joint set enters (a far field). The first region listed that
// contains a block wins; blocks in no region belong to the default region.
struct RegionInput {
  std::string name;
  Polygon polygon;
  bool jointed = true;
  double zone_size = 0.0;  // 0: the rock mass's
  std::string where;
};

// Slivers and tiny blocks: a block (not an opening) is merged into a neighbour if its area is
// below area_fraction * s^2 (s the smallest mean spacing of the sets; 0 = no sets: no area rule)
// or its roundness 4 pi A / P^2 (1 for a circle, 0.785 for a square, 0.06 for a 1:50 strip) is
// below `roundness`. The neighbour is the one of the same region (not an opening) with which it
// shares the longest boundary; their shared edges are removed. Smallest blocks first; a sliver
// with no such neighbour stays.
struct SliverRule {
  double area_fraction = 0.01;
  double roundness = 0.05;
};

struct RockMassInput {
  Polygon domain;
  std::string domain_where;
  std::vector<JointSetInput> joint_sets;
  std::vector<NamedJointInput> joints;
  std::vector<OpeningInput> openings;
  std::vector<RegionInput> regions;
  SliverRule sliver;
  std::uint64_t seed = 1;  // std::mt19937_64: the same seed gives the same blocks
};

// What a block edge is. joint: on a joint trace; bridge: on a joint line between traces (a rock
// bridge, UDEC/3DEC's fictitious joint); cut: a glued cut that is no joint (a region's or an
// opening's outline, a joint set's region outline, or the cut that splits a face with a hole);
// domain: the outer boundary.
enum class EdgeKind : std::uint8_t { joint, bridge, cut, domain };
struct EdgeTag {
  EdgeKind kind = EdgeKind::domain;
  // joint, bridge: the joint set's index, or joint_sets.size() + i for named joint i; else -1.
  int source = -1;
  bool operator==(const EdgeTag&) const = default;
};

struct RockMassBlock {
  // Counter-clockwise, starting at its lowest-x (then lowest-y) vertex. A block no joint cuts (an
  // opening; a block with no joint or bridge edge, such as a far field) has no vertex where
  // traces end on it, only its own corners (docs/rock-mass-generator.md).
  Polygon polygon;
  std::vector<EdgeTag> edges;  // edge i runs from polygon[i] to polygon[i + 1]
  int region = -1;             // index in RockMassInput::regions, -1 the default region
  int opening = -1;            // index in RockMassInput::openings, -1 if rock
};

// An interior edge of the cut rock mass, for inspection (traces and bridges).
struct RockMassSegment {
  Vec2 a = Vec2::Zero(), b = Vec2::Zero();
  EdgeTag tag;
};

struct RockMass {
  std::vector<RockMassBlock> blocks;  // ordered by their first vertex (x, then y), then second
  std::vector<RockMassSegment> segments;  // every edge between two blocks, once
  int slivers_merged = 0;
  int holes_split = 0;
};

// Opening outline as a counter-clockwise polygon.
Polygon opening_polygon(const OpeningInput& o);

// Cuts the domain. Throws InputError (naming the item's `where`) for degenerate input: a domain
// that is not simple, spacing <= 0, an opening or a region not inside the domain, openings that
// overlap, a joint set that cuts nothing, more than kMaxRockMassPieces joint pieces.
RockMass generate_rock_mass(const RockMassInput& in);
inline constexpr std::size_t kMaxRockMassPieces = 2'000'000;

// Labels of a block's boundary loop from the labels of its polygon's edges, when the loop (a
// mesh's boundary, or a rigid block's vertices) passes the polygon's vertex k at loop position
// corners[k] and runs counter-clockwise. `reversed`: the polygon was clockwise, so its edge k runs
// in the loop from corners[k + 1] to corners[k]. Every loop edge between two corners takes the
// label of the polygon edge it subdivides (TriMesh::corners for meshed blocks).
std::vector<int> loop_edge_labels(const std::vector<int>& polygon_labels, const std::vector<int>& corners,
                                  std::size_t loop_size, bool reversed);

// Total area shared by two or more of the polygons [m^2], computed exactly (CGAL Boolean set
// operations on each pair whose bounding boxes meet); 0 for blocks that only touch. For tests.
double total_overlap_area(const std::vector<Polygon>& polygons);

}  // namespace rockdem
