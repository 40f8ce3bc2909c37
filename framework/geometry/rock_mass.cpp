#include "framework/geometry/rock_mass.hpp"

#include <CGAL/Arr_consolidated_curve_data_traits_2.h>
#include <CGAL/Arr_segment_traits_2.h>
#include <CGAL/Arrangement_2.h>
#include <CGAL/Boolean_set_operations_2.h>
#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Polygon_2.h>
#include <CGAL/Polygon_2_algorithms.h>

#include <algorithm>
#include <iomanip>
#include <sstream>
#include <cmath>
#include <map>
#include <numbers>
#include <random>
#include <set>
#include <string>
#include <unordered_map>

#include "framework/core/error.hpp"

namespace rockdem {
namespace {

// Exact predicates and constructions: intersections of joints are exact rationals, so the
// arrangement never sees a near-coincidence it cannot decide.
using K = CGAL::Exact_predicates_exact_constructions_kernel;
using Point = K::Point_2;
using Segment = K::Segment_2;
using FT = K::FT;
// Every inserted segment carries the index of its CurveInfo; where segments overlap, the edge
// carries the indices of all of them.
using Traits = CGAL::Arr_consolidated_curve_data_traits_2<CGAL::Arr_segment_traits_2<K>, int>;
using Arr = CGAL::Arrangement_2<Traits>;
using Curve = Traits::Curve_2;
using Face = Arr::Face_const_handle;
using Halfedge = Arr::Halfedge_const_handle;
using ExactPolygon = CGAL::Polygon_2<K>;

// What an inserted segment is. Polygon outlines (domain, openings, regions, set regions) are
// inserted counter-clockwise, so their interior lies left of (a -> b).
enum class Role { domain, opening, region, set_region, joint, bridge, cut };
struct CurveInfo {
  Role role;
  int index;  // polygon's index (opening, region, set region), joint source (joint, bridge)
  Point a, b;
};

struct FaceInfo {
  int opening = -1, region = -1;
};

Point exact(const Vec2& v) { return Point(v.x(), v.y()); }
// The double nearest the exact value: a lazy number's own approximation depends on what was
// computed before (it can read -0 or 0 for an exact zero), which would break reproducibility.
Vec2 approx(const Point& p) { return {CGAL::to_double(CGAL::exact(p.x())), CGAL::to_double(CGAL::exact(p.y()))}; }

ExactPolygon exact_polygon(const Polygon& p) {
  ExactPolygon e;
  for (const Vec2& v : p) e.push_back(exact(v));
  if (e.is_clockwise_oriented()) e.reverse_orientation();
  return e;
}

double pwh_area(const CGAL::Polygon_with_holes_2<K>& p) {
  FT a = p.outer_boundary().area();
  for (auto h = p.holes_begin(); h != p.holes_end(); ++h) a += h->area();  // holes are clockwise
  return CGAL::to_double(a);
}

double shared_area(const ExactPolygon& a, const ExactPolygon& b) {
  std::vector<CGAL::Polygon_with_holes_2<K>> out;
  CGAL::intersection(a, b, std::back_inserter(out));
  double s = 0.0;
  for (const auto& p : out) s += pwh_area(p);
  return s;
}

bool contains(const ExactPolygon& outer, const ExactPolygon& inner) {
  std::vector<CGAL::Polygon_with_holes_2<K>> out;
  CGAL::difference(inner, outer, std::back_inserter(out));
  return out.empty();
}

class Cutter {
 public:
  explicit Cutter(const RockMassInput& in) : in_(in) {}
  RockMass run();

 private:
  void check_and_add_outlines();
  void add_polygon(const ExactPolygon& p, Role role, int index);
  void add_joint_sets();
  void add_joint_line(const JointSetInput& s, int set, Vec2 p, Vec2 d, std::mt19937_64& rng);
  void add_segment(const Point& a, const Point& b, Role role, int index, const std::string& where);
  bool inside(Face f, Role role, int index) const;
  FaceInfo info(Face f) const;
  bool keep(Halfedge e) const;
  void remove_edges();
  void remove_antennas();
  void check_sets_cut() const;
  bool split_one_face();
  bool merge_sliver_round(std::set<const void*>& stuck);
  EdgeTag tag(Halfedge e) const;
  // A vertex's coordinates in double, remembered: the sliver loop measures every face again after
  // each merge, and converting exact coordinates is costly. It only removes vertices, so an
  // entry never goes stale while the loop runs (the cache is cleared around it).
  Vec2 xy(Arr::Vertex_const_handle v);
  std::unordered_map<const void*, Vec2> xy_;
  RockMass output() const;

  const RockMassInput& in_;
  std::vector<CurveInfo> curves_;
  std::vector<Curve> pending_;
  std::vector<ExactPolygon> openings_, regions_, set_regions_;
  ExactPolygon domain_;
  Arr arr_;
  double xlo_ = 0, xhi_ = 0, ylo_ = 0, yhi_ = 0;  // domain bounding box, enlarged
  int holes_split_ = 0, slivers_merged_ = 0;
};

void Cutter::add_polygon(const ExactPolygon& p, Role role, int index) {
  for (auto e = p.edges_begin(); e != p.edges_end(); ++e) {
    pending_.emplace_back(*e, static_cast<int>(curves_.size()));
    curves_.push_back({role, index, e->source(), e->target()});
  }
}

void Cutter::add_segment(const Point& pa, const Point& pb, Role role, int index, const std::string& where) {
  if (pa == pb) return;
  if (pending_.size() >= kMaxRockMassPieces)
    throw InputError(where + ": more than " + std::to_string(kMaxRockMassPieces) +
                     " joint segments; increase the spacing or the trace length, or use a smaller domain");
  pending_.emplace_back(Segment(pa, pb), static_cast<int>(curves_.size()));
  curves_.push_back({role, index, pa, pb});
}

void Cutter::check_and_add_outlines() {
  Polygon d = in_.domain;
  if (d.size() < 3 || !is_simple(d))
    throw InputError(in_.domain_where + ": the domain must be a simple polygon (at least 3 vertices, no crossing or "
                     "touching edges, non-zero area)");
  make_ccw(d);
  domain_ = exact_polygon(d);
  xlo_ = xhi_ = d[0].x();
  ylo_ = yhi_ = d[0].y();
  for (const Vec2& v : d) {
    xlo_ = std::min(xlo_, v.x()), xhi_ = std::max(xhi_, v.x());
    ylo_ = std::min(ylo_, v.y()), yhi_ = std::max(yhi_, v.y());
  }
  const double pad = 0.01 * std::max(xhi_ - xlo_, yhi_ - ylo_);
  xlo_ -= pad, xhi_ += pad, ylo_ -= pad, yhi_ += pad;
  add_polygon(domain_, Role::domain, 0);

  for (std::size_t i = 0; i < in_.openings.size(); ++i) {
    const OpeningInput& o = in_.openings[i];
    const Polygon p = opening_polygon(o);
    if (!is_simple(p)) throw InputError(o.where + ": opening '" + o.name + "' is not a simple polygon");
    openings_.push_back(exact_polygon(p));
    if (!contains(domain_, openings_.back()))
      throw InputError(o.where + ": opening '" + o.name + "' is not inside the domain; an opening must lie within "
                       "the domain polygon (it may touch its boundary)");
    for (std::size_t j = 0; j < i; ++j)
      if (shared_area(openings_[j], openings_.back()) > 0.0)
        throw InputError(o.where + ": opening '" + o.name + "' overlaps opening '" + in_.openings[j].name +
                         "'; openings may touch but not overlap");
    add_polygon(openings_.back(), Role::opening, static_cast<int>(i));
  }
  for (std::size_t i = 0; i < in_.regions.size(); ++i) {
    const RegionInput& r = in_.regions[i];
    if (r.polygon.size() < 3 || !is_simple(r.polygon))
      throw InputError(r.where + ": region '" + r.name + "' is not a simple polygon");
    regions_.push_back(exact_polygon(r.polygon));
    if (!(shared_area(domain_, regions_.back()) > 0.0))
      throw InputError(r.where + ": region '" + r.name + "' lies outside the domain; a region must overlap the "
                       "domain polygon");
    add_polygon(regions_.back(), Role::region, static_cast<int>(i));
  }
}

// Values drawn from N(mean, sd), kept at least 10 % of the mean so that a wide spread cannot make
// a zero or negative spacing or length.
double draw(std::mt19937_64& rng, double mean, double sd) {
  if (!(sd > 0.0)) return mean;
  std::normal_distribution<double> n(mean, sd);
  return std::max(0.1 * mean, n(rng));
}

// One joint: the line p + t d across the enlarged bounding box, cut into alternating trace and
// gap (bridge) pieces starting at a seeded phase.
void Cutter::add_joint_line(const JointSetInput& s, int set, Vec2 p, Vec2 d, std::mt19937_64& rng) {
  // Liang-Barsky clip of the line against the box.
  double t0 = -std::numeric_limits<double>::infinity(), t1 = std::numeric_limits<double>::infinity();
  const double lo[2] = {xlo_, ylo_}, hi[2] = {xhi_, yhi_};
  for (int k = 0; k < 2; ++k) {
    if (std::abs(d[k]) < 1e-15) {
      if (p[k] < lo[k] || p[k] > hi[k]) return;
      continue;
    }
    double a = (lo[k] - p[k]) / d[k], b = (hi[k] - p[k]) / d[k];
    if (a > b) std::swap(a, b);
    t0 = std::max(t0, a), t1 = std::min(t1, b);
  }
  if (!(t1 > t0)) return;
  // Pieces are built exactly as anchor + t d, so that all pieces of a joint are collinear and the
  // joint passes exactly through its anchor (joints of several sets through one origin meet there
  // in one vertex, not in a cluster of nearby ones).
  const Point anchor = exact(p);
  const K::Vector_2 dir(d.x(), d.y());
  const auto at = [&](double t) { return anchor + FT(t) * dir; };
  const bool persistent = !std::isfinite(s.trace) || !(s.gap > 0.0);
  if (persistent) {
    add_segment(at(t0), at(t1), Role::joint, set, s.where);
    return;
  }
  std::uniform_real_distribution<double> phase(0.0, s.trace + s.gap);
  double t = t0 - phase(rng);
  bool trace = true;
  while (t < t1) {
    const double len = trace ? draw(rng, s.trace, s.trace_sd) : draw(rng, s.gap, s.gap_sd);
    const double a = std::max(t, t0), b = std::min(t + len, t1);
    if (b > a) add_segment(at(a), at(b), trace ? Role::joint : Role::bridge, set, s.where);
    t += len;
    trace = !trace;
  }
}

namespace {
// Bounds that keep a joint set finite in time and memory (a model with more traces than this in
// one set is far beyond what the arrangement and the engine handle anyway).
constexpr double kMaxSpacingSteps = 1e6;
constexpr double kMaxTraces = 1e5;
}  // namespace

void Cutter::add_joint_sets() {
  std::mt19937_64 rng(in_.seed);
  for (std::size_t i = 0; i < in_.joint_sets.size(); ++i) {
    const JointSetInput& s = in_.joint_sets[i];
    if (!(s.spacing > 0.0) || !std::isfinite(s.spacing))
      throw InputError(s.where + ": joint set '" + s.name + "' needs a spacing > 0");
    if (!(s.trace > 0.0) || s.gap < 0.0)
      throw InputError(s.where + ": joint set '" + s.name + "' needs a trace length > 0 and a gap >= 0");
    if (s.dip_sd < 0.0 || s.spacing_sd < 0.0 || s.trace_sd < 0.0 || s.gap_sd < 0.0)
      throw InputError(s.where + ": joint set '" + s.name + "': standard deviations must be >= 0");
    const Polygon* extent = &in_.domain;
    if (s.region) {
      if (s.region->size() < 3 || !is_simple(*s.region))
        throw InputError(s.where + ": the region of joint set '" + s.name + "' is not a simple polygon");
      set_regions_.push_back(exact_polygon(*s.region));
      add_polygon(set_regions_.back(), Role::set_region, static_cast<int>(i));
      extent = &*s.region;
    } else {
      set_regions_.emplace_back();
    }
    const Vec2 n(std::sin(s.dip), std::cos(s.dip));  // normal of the mean joint
    double smin = std::numeric_limits<double>::infinity(), smax = -smin;
    for (const Vec2& v : *extent) {
      smin = std::min(smin, (v - s.origin).dot(n));
      smax = std::max(smax, (v - s.origin).dot(n));
    }
    // The walk below steps from the origin, one spacing at a time, so an origin far outside the
    // extent or a spacing tiny against it would run for ever (an origin 9e18 m away was found by
    // the parser replay, tests/fuzz/); such sets are refused with the numbers.
    const double walk = std::max({smax, -smin, 0.0}) / s.spacing, traces = (smax - smin) / s.spacing;
    Vec2 lo = (*extent)[0], hi = (*extent)[0];
    for (const Vec2& v : *extent) {
      lo = lo.cwiseMin(v);
      hi = hi.cwiseMax(v);
    }
    const double along = (hi - lo).norm() / (s.trace + s.gap);  // trace-gap pieces on the longest line
    const auto g = [](double x) {
      std::ostringstream os;
      os << std::setprecision(3) << x;
      return os.str();
    };
    const std::string within = s.region ? "its region" : "the domain";
    if (!(traces <= kMaxTraces))
      throw InputError(s.where + ": a spacing of " + g(s.spacing) + " m makes " + g(traces) + " parallel traces across " +
                       within + "; valid: at most " + g(kMaxTraces));
    if (!(walk <= kMaxSpacingSteps))
      throw InputError(s.where + ": the origin lies " + g(walk) + " spacings from the farthest point of " + within +
                       "; valid: within " + g(kMaxSpacingSteps) + " spacings (put the origin near the model)");
    const bool persistent = !std::isfinite(s.trace) || !(s.gap > 0.0);  // as add_joint_line: not cut
    if (!persistent && !(along <= kMaxTraces))
      throw InputError(s.where + ": trace plus gap of " + g(s.trace + s.gap) + " m cuts each line across " + within +
                       " into about " + g(along) + " pieces; valid: at most " + g(kMaxTraces));
    const auto joint = [&](double at) {
      const double dip = s.dip_sd > 0.0 ? std::normal_distribution<double>(s.dip, s.dip_sd)(rng) : s.dip;
      add_joint_line(s, static_cast<int>(i), s.origin + at * n, Vec2(std::cos(dip), -std::sin(dip)), rng);
    };
    // Positions normal to the set: from the origin outwards, first the positive side, then the
    // negative, each step a drawn spacing.
    for (double at = 0.0; at <= smax; at += draw(rng, s.spacing, s.spacing_sd))
      if (at >= smin) joint(at);
    for (double at = -draw(rng, s.spacing, s.spacing_sd); at >= smin; at -= draw(rng, s.spacing, s.spacing_sd))
      if (at <= smax) joint(at);
  }
  const int first_named = static_cast<int>(in_.joint_sets.size());
  for (std::size_t j = 0; j < in_.joints.size(); ++j) {
    const NamedJointInput& nj = in_.joints[j];
    if (!((nj.b - nj.a).norm() > 0.0))
      throw InputError(nj.where + ": joint '" + nj.name + "' has two equal end points");
    add_segment(exact(nj.a), exact(nj.b), Role::joint, first_named + static_cast<int>(j), nj.where);
  }
}

// Whether face f lies inside the polygon (role, index), every edge of which is in the
// arrangement. A halfedge of f's outer boundary has f on its left: if it lies on the polygon's
// outline, f is inside when it runs the way the (counter-clockwise) outline does; otherwise the
// halfedge does not touch the outline except at its ends, and its midpoint tells.
bool Cutter::inside(Face f, Role role, int index) const {
  if (f->is_unbounded()) return false;
  const Halfedge e = f->outer_ccb();
  for (int c : e->curve().data()) {
    const CurveInfo& ci = curves_[static_cast<std::size_t>(c)];
    if (ci.role == role && ci.index == index)
      return (e->target()->point() - e->source()->point()) * (ci.b - ci.a) > 0;
  }
  const ExactPolygon& p = role == Role::domain    ? domain_
                          : role == Role::opening ? openings_[static_cast<std::size_t>(index)]
                          : role == Role::region  ? regions_[static_cast<std::size_t>(index)]
                                                  : set_regions_[static_cast<std::size_t>(index)];
  const Point mid = CGAL::midpoint(e->source()->point(), e->target()->point());
  return p.bounded_side(mid) == CGAL::ON_BOUNDED_SIDE;
}

FaceInfo Cutter::info(Face f) const {
  FaceInfo fi;
  for (std::size_t i = 0; i < openings_.size() && fi.opening < 0; ++i)
    if (inside(f, Role::opening, static_cast<int>(i))) fi.opening = static_cast<int>(i);
  for (std::size_t i = 0; i < regions_.size() && fi.region < 0; ++i)
    if (inside(f, Role::region, static_cast<int>(i))) fi.region = static_cast<int>(i);
  return fi;
}

// An edge stays if one of its segments cuts there: the domain outline always; opening, region and
// set-region outlines inside the domain (glued cuts: a set's joints end on its region's outline,
// which must cut so that the blocks close); a joint or bridge piece if one side of it is inside
// the domain, outside every opening, in a jointed region and inside its set's region.
bool Cutter::keep(Halfedge e) const {
  const Face f[2] = {e->face(), e->twin()->face()};
  bool in_domain[2], info_done[2] = {false, false};
  FaceInfo fi[2];
  for (int k = 0; k < 2; ++k) in_domain[k] = inside(f[k], Role::domain, 0);
  for (int c : e->curve().data()) {
    const CurveInfo& ci = curves_[static_cast<std::size_t>(c)];
    switch (ci.role) {
      case Role::domain: return true;
      case Role::opening:
      case Role::region:
      case Role::set_region:
      case Role::cut:
        if (in_domain[0] || in_domain[1]) return true;
        break;
      case Role::joint:
      case Role::bridge:
        for (int k = 0; k < 2; ++k) {
          if (!in_domain[k]) continue;
          if (!info_done[k]) fi[k] = info(f[k]), info_done[k] = true;
          if (fi[k].opening >= 0) continue;
          if (fi[k].region >= 0 && !in_.regions[static_cast<std::size_t>(fi[k].region)].jointed) continue;
          if (ci.index < static_cast<int>(in_.joint_sets.size()) &&
              in_.joint_sets[static_cast<std::size_t>(ci.index)].region && !inside(f[k], Role::set_region, ci.index))
            continue;
          return true;
        }
        break;
    }
  }
  return false;
}

void Cutter::remove_edges() {
  std::vector<Arr::Halfedge_handle> drop;
  for (auto e = arr_.edges_begin(); e != arr_.edges_end(); ++e)
    if (!keep(e)) drop.push_back(e);
  for (auto e : drop) arr_.remove_edge(e);
}

// Edges with the same face on both sides (a joint ending inside a block) cut nothing.
void Cutter::remove_antennas() {
  for (;;) {
    std::vector<Arr::Halfedge_handle> drop;
    for (auto e = arr_.edges_begin(); e != arr_.edges_end(); ++e)
      if (e->face() == e->twin()->face()) drop.push_back(e);
    if (drop.empty()) break;
    for (auto e : drop) arr_.remove_edge(e);
  }
  std::vector<Arr::Vertex_handle> isolated;
  for (auto v = arr_.vertices_begin(); v != arr_.vertices_end(); ++v)
    if (v->is_isolated()) isolated.push_back(v);
  for (auto v : isolated) arr_.remove_isolated_vertex(v);
}

void Cutter::check_sets_cut() const {
  std::vector<bool> cuts(in_.joint_sets.size() + in_.joints.size(), false);
  for (auto e = arr_.edges_begin(); e != arr_.edges_end(); ++e)
    for (int c : e->curve().data()) {
      const CurveInfo& ci = curves_[static_cast<std::size_t>(c)];
      if (ci.role == Role::joint || ci.role == Role::bridge) cuts[static_cast<std::size_t>(ci.index)] = true;
    }
  for (std::size_t i = 0; i < in_.joint_sets.size(); ++i)
    if (!cuts[i])
      throw InputError(in_.joint_sets[i].where + ": joint set '" + in_.joint_sets[i].name +
                       "' cuts no block: none of its joints crosses the jointed part of the domain" +
                       (in_.joint_sets[i].region ? " inside its region" : "") +
                       "; check its origin, spacing and region");
  for (std::size_t j = 0; j < in_.joints.size(); ++j)
    if (!cuts[in_.joint_sets.size() + j])
      throw InputError(in_.joints[j].where + ": joint '" + in_.joints[j].name +
                       "' cuts no block: it must cross a block of the jointed domain from boundary to boundary");
}

// The outline of a boundary cycle as an exact polygon (for point-in-polygon tests).
template <class Ccb>
ExactPolygon ccb_polygon(Ccb first) {
  ExactPolygon p;
  auto c = first;
  do p.push_back(c->source()->point());
  while (++c != first);
  return p;
}

// A block is one boundary loop: a face with a hole, or whose boundary passes a vertex twice, is
// split along the vertical line x = xc through it (the hole's middle, between its two middle
// distinct vertex abscissae so that the line meets no hole vertex; or the repeated vertex). The
// parts of that line inside the face become glued cuts. Returns false if no face needed it.
bool Cutter::split_one_face() {
  for (auto f = arr_.faces_begin(); f != arr_.faces_end(); ++f) {
    if (f->is_unbounded()) continue;
    std::optional<FT> xc;
    if (f->number_of_inner_ccbs() > 0) {
      std::vector<FT> xs;
      auto c = *f->inner_ccbs_begin();
      auto h = c;
      do xs.push_back(h->source()->point().x());
      while (++h != c);
      std::sort(xs.begin(), xs.end());
      xs.erase(std::unique(xs.begin(), xs.end()), xs.end());
      if (xs.size() < 2) continue;
      const std::size_t k = xs.size() / 2;
      xc = (xs[k - 1] + xs[k]) / 2;
    } else {
      std::set<const void*> seen;
      auto c = f->outer_ccb();
      auto h = c;
      do {
        if (!seen.insert(&*h->source()).second) {
          xc = h->source()->point().x();
          break;
        }
      } while (++h != c);
    }
    if (!xc) continue;
    const ExactPolygon outer = ccb_polygon(f->outer_ccb());
    std::vector<ExactPolygon> holes;
    for (auto hc = f->inner_ccbs_begin(); hc != f->inner_ccbs_end(); ++hc) holes.push_back(ccb_polygon(*hc));
    const int id = static_cast<int>(curves_.size());
    const Point a(*xc, FT(ylo_)), b(*xc, FT(yhi_));
    curves_.push_back({Role::cut, -1, a, b});
    CGAL::insert(arr_, Curve(Segment(a, b), id));
    std::vector<Arr::Halfedge_handle> drop;
    for (auto e = arr_.edges_begin(); e != arr_.edges_end(); ++e) {
      const auto& data = e->curve().data();
      if (data.size() != 1 || *data.begin() != id) continue;
      const Point mid = CGAL::midpoint(e->source()->point(), e->target()->point());
      bool in = CGAL::bounded_side_2(outer.vertices_begin(), outer.vertices_end(), mid, K()) == CGAL::ON_BOUNDED_SIDE;
      for (const auto& h : holes)
        if (in && CGAL::bounded_side_2(h.vertices_begin(), h.vertices_end(), mid, K()) != CGAL::ON_UNBOUNDED_SIDE)
          in = false;
      if (!in) drop.push_back(e);
    }
    for (auto e : drop) arr_.remove_edge(e);
    ++holes_split_;
    return true;
  }
  return false;
}

Vec2 Cutter::xy(Arr::Vertex_const_handle v) {
  auto [it, added] = xy_.try_emplace(&*v);
  if (added) it->second = approx(v->point());
  return it->second;
}

struct FaceStats {
  double area = 0.0, perimeter = 0.0;
  FaceInfo info;
  Point lowest;  // lowest (x, then y) vertex
};

// One round of sliver merging. Slivers are taken smallest first (ties: lowest vertex first); each
// is merged into the neighbour of the same region (not an opening) with which it shares the
// longest boundary, by removing the edges between them. A sliver next to a face already merged
// in this round waits for the next round, when that face has been measured again, so the result
// is that of merging one smallest sliver at a time. `stuck` holds slivers with no eligible
// neighbour. Returns whether anything changed.
bool Cutter::merge_sliver_round(std::set<const void*>& stuck) {
  double min_spacing = std::numeric_limits<double>::infinity();
  for (const auto& s : in_.joint_sets) min_spacing = std::min(min_spacing, s.spacing);
  const double min_area = std::isfinite(min_spacing) ? in_.sliver.area_fraction * min_spacing * min_spacing : 0.0;
  std::unordered_map<const void*, FaceStats> stats;
  std::vector<std::pair<const void*, Arr::Face_handle>> slivers;
  for (auto f = arr_.faces_begin(); f != arr_.faces_end(); ++f) {
    if (f->is_unbounded()) continue;
    FaceStats st;
    Polygon p;
    auto c = f->outer_ccb();
    auto h = c;
    st.lowest = h->source()->point();
    do {
      p.push_back(xy(h->source()));
      st.perimeter += (xy(h->target()) - p.back()).norm();
      if (CGAL::compare_xy(h->source()->point(), st.lowest) == CGAL::SMALLER) st.lowest = h->source()->point();
    } while (++h != c);
    st.area = signed_area(p);
    st.info = info(f);
    stats[&*f] = st;
    if (st.info.opening >= 0 || stuck.count(&*f)) continue;
    const double roundness = 4.0 * std::numbers::pi * st.area / (st.perimeter * st.perimeter);
    if (st.area < min_area || roundness < in_.sliver.roundness) slivers.emplace_back(&*f, f);
  }
  std::sort(slivers.begin(), slivers.end(), [&](const auto& x, const auto& y) {
    const FaceStats &sx = stats[x.first], &sy = stats[y.first];
    if (sx.area != sy.area) return sx.area < sy.area;
    return CGAL::compare_xy(sx.lowest, sy.lowest) == CGAL::SMALLER;
  });
  // Equal shared lengths (to 1e-9 relative) go to the neighbour with the lowest (x, then y)
  // vertex, so that the choice does not depend on where faces sit in memory.
  const auto better = [](const std::pair<double, Point>& x, const std::pair<double, Point>& y) {
    if (std::abs(x.first - y.first) > 1e-9 * std::max(x.first, y.first)) return x.first > y.first;
    return CGAL::compare_xy(x.second, y.second) == CGAL::SMALLER;
  };
  std::set<const void*> touched;
  bool changed = false;
  for (const auto& [key, face] : slivers) {
    if (touched.count(key)) continue;
    std::map<const void*, std::pair<double, Point>> shared;  // neighbour: shared length, its lowest vertex
    bool wait = false;
    auto c = face->outer_ccb();
    auto h = c;
    do {
      const Face g = h->twin()->face();
      if (g->is_unbounded()) continue;
      if (touched.count(&*g)) wait = true;
      const FaceStats& gs = stats[&*g];
      if (gs.info.opening >= 0 || gs.info.region != stats[key].info.region) continue;
      auto& [length, lowest] = shared.try_emplace(&*g, 0.0, gs.lowest).first->second;
      length += (xy(h->target()) - xy(h->source())).norm();
    } while (++h != c);
    if (wait) continue;
    changed = true;
    if (shared.empty()) {
      stuck.insert(key);
      continue;
    }
    auto pick = shared.begin();
    for (auto it = shared.begin(); it != shared.end(); ++it)
      if (better(it->second, pick->second)) pick = it;
    const void* neighbour = pick->first;
    std::vector<Arr::Halfedge_handle> drop;
    auto d = face->outer_ccb();
    auto e = d;
    do
      if (&*e->twin()->face() == neighbour) drop.push_back(e);
    while (++e != d);
    touched.insert(key);
    touched.insert(neighbour);
    for (auto x : drop) arr_.remove_edge(x);
    ++slivers_merged_;
  }
  return changed;
}

// The edge's label, by priority: the domain outline, a joint trace (lowest source first), a
// bridge, a glued cut.
EdgeTag Cutter::tag(Halfedge e) const {
  EdgeTag best{EdgeKind::cut, -1};
  bool found = false;
  for (int c : e->curve().data()) {
    const CurveInfo& ci = curves_[static_cast<std::size_t>(c)];
    EdgeTag t;
    if (ci.role == Role::domain) return {EdgeKind::domain, -1};
    if (ci.role == Role::joint) t = {EdgeKind::joint, ci.index};
    else if (ci.role == Role::bridge) t = {EdgeKind::bridge, ci.index};
    else continue;
    if (!found || static_cast<int>(t.kind) < static_cast<int>(best.kind) ||
        (t.kind == best.kind && t.source < best.source))
      best = t, found = true;
  }
  return best;
}

// Blocks no joint cuts (an opening, or a block whose outline has no joint or bridge on it: a far
// field, whether an unjointed region or rock the joint sets' regions leave out) keep only their
// true corners. Where joint traces end on such a block's outline the arrangement leaves a vertex
// at each end, and there the block's boundary point lies exactly on the corners of the two
// jointed blocks the trace separates: three coincident points, where contacts chattered and the
// drift study's static stages stalled (docs/drift-study.md). Without those vertices the jointed
// blocks' corners meet a flat face, and the block's own boundary points (the mesher's, zone_size
// apart) meet the jointed blocks' faces. A vertex goes only where its two edges are exactly
// collinear, run on in the same direction and carry the same label, so the outline, the area
// and the labels stay as they were.
void drop_flat_vertices(std::vector<Point>& pts, std::vector<EdgeTag>& edges) {
  bool dropped = true;
  while (dropped && pts.size() > 3) {  // dropping a vertex can make its neighbour flat
    dropped = false;
    for (std::size_t i = 0; pts.size() > 3 && i < pts.size(); ++i) {
      const std::size_t n = pts.size(), ip = (i + n - 1) % n, in = (i + 1) % n;
      if (edges[ip] == edges[i] && CGAL::collinear(pts[ip], pts[i], pts[in]) &&
          CGAL::collinear_are_strictly_ordered_along_line(pts[ip], pts[i], pts[in])) {
        pts.erase(pts.begin() + static_cast<std::ptrdiff_t>(i));
        edges.erase(edges.begin() + static_cast<std::ptrdiff_t>(i));  // edge ip now runs on to pts[in]
        dropped = true;
      }
    }
  }
}

RockMass Cutter::output() const {
  RockMass rm;
  rm.holes_split = holes_split_;
  rm.slivers_merged = slivers_merged_;
  struct Loop {
    std::vector<Point> pts;
    RockMassBlock block;
  };
  std::vector<Loop> loops;
  for (auto f = arr_.faces_begin(); f != arr_.faces_end(); ++f) {
    if (f->is_unbounded()) continue;
    Loop l;
    auto c = f->outer_ccb();
    auto h = c;
    do {
      l.pts.push_back(h->source()->point());
      l.block.edges.push_back(tag(h));
    } while (++h != c);
    const FaceInfo fi = info(f);
    const bool uncut = std::none_of(l.block.edges.begin(), l.block.edges.end(), [](const EdgeTag& t) {
      return t.kind == EdgeKind::joint || t.kind == EdgeKind::bridge;
    });
    if (fi.opening >= 0 || uncut) drop_flat_vertices(l.pts, l.block.edges);
    // Start at the lowest (x, then y) vertex so that the order does not depend on CGAL's.
    const auto first = std::min_element(l.pts.begin(), l.pts.end(),
                                        [](const Point& a, const Point& b) { return CGAL::compare_xy(a, b) == CGAL::SMALLER; });
    const auto shift = first - l.pts.begin();
    std::rotate(l.pts.begin(), first, l.pts.end());
    std::rotate(l.block.edges.begin(), l.block.edges.begin() + shift, l.block.edges.end());
    for (const Point& p : l.pts) l.block.polygon.push_back(approx(p));
    l.block.region = fi.region;
    l.block.opening = fi.opening;
    loops.push_back(std::move(l));
  }
  std::sort(loops.begin(), loops.end(), [](const Loop& a, const Loop& b) {
    const auto r = CGAL::compare_xy(a.pts[0], b.pts[0]);
    if (r != CGAL::EQUAL) return r == CGAL::SMALLER;
    return CGAL::compare_xy(a.pts[1], b.pts[1]) == CGAL::SMALLER;
  });
  for (auto& l : loops) rm.blocks.push_back(std::move(l.block));
  for (auto e = arr_.edges_begin(); e != arr_.edges_end(); ++e)
    if (!e->face()->is_unbounded() && !e->twin()->face()->is_unbounded())
      rm.segments.push_back({approx(e->source()->point()), approx(e->target()->point()), tag(e)});
  return rm;
}

RockMass Cutter::run() {
  if (!(in_.sliver.area_fraction >= 0.0) || !(in_.sliver.roundness >= 0.0) || in_.sliver.roundness >= 1.0)
    throw InputError(in_.domain_where + ": the sliver rule needs area_fraction >= 0 and roundness in [0, 1)");
  check_and_add_outlines();
  add_joint_sets();
  CGAL::insert(arr_, pending_.begin(), pending_.end());
  pending_.clear();
  remove_edges();
  remove_antennas();
  check_sets_cut();
  // Faces with holes are split first so that every sliver is measured as the block it would be;
  // merging can make a face with a hole again, so splitting runs once more after it.
  while (split_one_face()) {}
  std::set<const void*> stuck;
  xy_.clear();
  while (merge_sliver_round(stuck)) remove_antennas();
  xy_.clear();
  while (split_one_face()) {}
  return output();
}

}  // namespace

Polygon opening_polygon(const OpeningInput& o) {
  Polygon p;
  const double pi = std::numbers::pi;
  switch (o.shape) {
    case OpeningInput::Shape::circle: {
      if (!(o.radius > 0.0) || o.segments < 3)
        throw InputError(o.where + ": a circular opening needs radius > 0 and at least 3 segments");
      for (int k = 0; k < o.segments; ++k) {
        const double a = 2.0 * pi * k / o.segments;
        p.emplace_back(o.centre.x() + o.radius * std::cos(a), o.centre.y() + o.radius * std::sin(a));
      }
      return p;
    }
    case OpeningInput::Shape::horseshoe: {
      const double w = o.width, h = o.wall_height, r = o.arch_rise > 0.0 ? o.arch_rise : 0.5 * o.width;
      if (!(w > 0.0) || !(h > 0.0) || o.segments < 2 || r > 0.5 * w + 1e-12 * w)
        throw InputError(o.where + ": a horseshoe opening needs width > 0, wall_height > 0, 0 < arch_rise <= width/2 and "
                         "at least 2 arch segments");
      // The arch is a circular arc through both wall tops and the crown, r above them.
      const double radius = (0.25 * w * w + r * r) / (2.0 * r);
      const Vec2 c(o.centre.x(), o.centre.y() + h + r - radius);
      const double a0 = std::atan2(radius - r, 0.5 * w);
      p = {{o.centre.x() - 0.5 * w, o.centre.y()}, {o.centre.x() + 0.5 * w, o.centre.y()}, {o.centre.x() + 0.5 * w, o.centre.y() + h}};
      for (int k = 1; k < o.segments; ++k) {
        const double a = a0 + (pi - 2.0 * a0) * k / o.segments;
        p.emplace_back(c.x() + radius * std::cos(a), c.y() + radius * std::sin(a));
      }
      p.emplace_back(o.centre.x() - 0.5 * w, o.centre.y() + h);
      return p;
    }
    case OpeningInput::Shape::polygon:
      p = o.polygon;
      if (p.size() < 3) throw InputError(o.where + ": a polygon opening needs at least 3 vertices");
      make_ccw(p);
      return p;
  }
  return p;
}

RockMass generate_rock_mass(const RockMassInput& in) { return Cutter(in).run(); }

std::vector<int> loop_edge_labels(const std::vector<int>& polygon_labels, const std::vector<int>& corners,
                                  std::size_t loop_size, bool reversed) {
  std::vector<int> out(loop_size, -1);
  const std::size_t n = corners.size();
  if (polygon_labels.size() != n || loop_size == 0) return out;
  for (std::size_t k = 0; k < n; ++k) {
    const auto a = static_cast<std::size_t>(corners[k]), b = static_cast<std::size_t>(corners[(k + 1) % n]);
    const std::size_t from = reversed ? b : a, to = reversed ? a : b;
    std::size_t j = from;
    do {
      out[j] = polygon_labels[k];
      j = (j + 1) % loop_size;
    } while (j != to);
  }
  return out;
}

double total_overlap_area(const std::vector<Polygon>& polygons) {
  std::vector<ExactPolygon> ex;
  std::vector<CGAL::Bbox_2> box;
  for (const auto& p : polygons) {
    ex.push_back(exact_polygon(p));
    box.push_back(ex.back().bbox());
  }
  double total = 0.0;
  for (std::size_t i = 0; i < ex.size(); ++i)
    for (std::size_t j = i + 1; j < ex.size(); ++j)
      if (CGAL::do_overlap(box[i], box[j])) total += shared_area(ex[i], ex[j]);
  return total;
}

}  // namespace rockdem
