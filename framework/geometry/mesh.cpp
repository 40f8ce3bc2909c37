#include "framework/geometry/mesh.hpp"

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Delaunay_mesh_face_base_2.h>
#include <CGAL/Delaunay_mesh_size_criteria_2.h>
#include <CGAL/Delaunay_mesh_vertex_base_2.h>
#include <CGAL/Delaunay_mesher_2.h>
#include <CGAL/Delaunay_mesher_no_edge_refinement_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <string>

#include "framework/core/error.hpp"

namespace rockdem {

namespace {
using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Vb = CGAL::Delaunay_mesh_vertex_base_2<K>;
using Fb = CGAL::Delaunay_mesh_face_base_2<K>;
using Tds = CGAL::Triangulation_data_structure_2<Vb, Fb>;
using CDT = CGAL::Constrained_Delaunay_triangulation_2<K, Tds>;
using Criteria = CGAL::Delaunay_mesh_size_criteria_2<CDT>;
using Point = CDT::Point;

// Renumber so that the boundary loop comes first (node i == boundary[i]), keeping the rest in
// their original order.
TriMesh renumber_boundary_first(const std::vector<Vec2>& nodes, const std::vector<std::array<int, 3>>& tris,
                                const std::vector<int>& loop, const std::vector<int>& corners) {
  const int n = static_cast<int>(nodes.size());
  std::vector<int> newid(n, -1);
  TriMesh m;
  m.nodes.reserve(n);
  for (int v : loop) {
    newid[v] = static_cast<int>(m.nodes.size());
    m.nodes.push_back(nodes[v]);
  }
  for (int v = 0; v < n; ++v)
    if (newid[v] < 0) {
      newid[v] = static_cast<int>(m.nodes.size());
      m.nodes.push_back(nodes[v]);
    }
  m.triangles.reserve(tris.size());
  for (const auto& t : tris) m.triangles.push_back({newid[t[0]], newid[t[1]], newid[t[2]]});
  for (size_t i = 0; i < loop.size(); ++i) m.boundary.push_back(static_cast<int>(i));
  for (int c : corners) m.corners.push_back(newid[c]);
  return m;
}

}  // namespace

TriMesh mesh_polygon(const Polygon& polygon_in, double zone_size) {
  if (!(zone_size > 0.0) || !std::isfinite(zone_size))
    throw InputError("mesh_polygon: zone size must be a positive length, got " + std::to_string(zone_size));
  Polygon poly = polygon_in;
  if (!is_simple(poly))
    throw InputError("mesh_polygon: block outline is not a simple polygon (needs >= 3 distinct vertices, "
                     "non-zero area and no crossing or touching edges)");
  make_ccw(poly);
  const size_t nv = poly.size();

  // Split every edge evenly first: boundary gridpoints end up evenly spaced along each face,
  // which contact lengths and applied tractions rely on; the refinement rarely splits further.
  std::vector<Point> ring;
  std::vector<size_t> corner_pos;
  for (size_t i = 0; i < nv; ++i) {
    const Vec2 a = poly[i], b = poly[(i + 1) % nv];
    const int k = std::max(1, static_cast<int>(std::ceil((b - a).norm() / zone_size - 1e-9)));
    corner_pos.push_back(ring.size());
    for (int j = 0; j < k; ++j) {
      const Vec2 p = (j == 0) ? a : Vec2(a + (b - a) * (static_cast<double>(j) / k));
      ring.emplace_back(p.x(), p.y());
    }
  }
  // Refinement without splitting the constrained edges keeps the even boundary spacing; it
  // cannot insert circumcentres that encroach on the boundary, so its angle bound is not
  // guaranteed (measured: > 26 degrees on blocks, wedges and L shapes, longest edges up to
  // ~1.3 zone_size). If it leaves a zone under 20 degrees, the full Ruppert refinement (which may
  // split boundary edges further) is used instead.
  auto build = [&](CDT& cdt, std::vector<CDT::Vertex_handle>& vh, bool split_edges) {
    vh.clear();
    for (const auto& p : ring) vh.push_back(cdt.insert(p));
    for (size_t i = 0; i < vh.size(); ++i) cdt.insert_constraint(vh[i], vh[(i + 1) % vh.size()]);
    // The domain is the bounded region enclosed by the constraints (no seeds needed).
    if (split_edges) {
      CGAL::refine_Delaunay_mesh_2(cdt, Criteria(0.125, zone_size));
    } else {
      CGAL::Delaunay_mesher_no_edge_refinement_2<CDT, Criteria> mesher(cdt, Criteria(0.125, zone_size));
      // CGAL 5.5's constructors leave the seeds' mark uninitialised (Delaunay_mesher_2's set it to
      // false) and refine_mesh() reads it: undefined behaviour that UBSan reports, though with no
      // seeds the value is never used. clear_seeds() sets it.
      mesher.clear_seeds();
      mesher.refine_mesh();
    }
  };
  auto min_angle = [](const CDT& cdt) {
    double worst = 1.0;  // smallest sine of an angle
    for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f) {
      if (!f->is_in_domain()) continue;
      for (int i = 0; i < 3; ++i) {
        const auto& a = f->vertex(i)->point();
        const auto u = f->vertex((i + 1) % 3)->point() - a, v = f->vertex((i + 2) % 3)->point() - a;
        const double s = (u.x() * v.y() - u.y() * v.x()) / std::sqrt(u.squared_length() * v.squared_length());
        worst = std::min(worst, s);
      }
    }
    return std::asin(worst) * 180.0 / std::numbers::pi;
  };
  CDT cdt;
  std::vector<CDT::Vertex_handle> vh;
  build(cdt, vh, false);
  if (min_angle(cdt) < 20.0) {
    CDT full;
    std::vector<CDT::Vertex_handle> vfull;
    build(full, vfull, true);
    if (min_angle(full) > min_angle(cdt)) {
      cdt.swap(full);
      vh.swap(vfull);
    }
  }

  std::map<CDT::Vertex_handle, int> id;
  std::vector<Vec2> nodes;
  std::vector<std::array<int, 3>> tris;
  auto node_of = [&](CDT::Vertex_handle v) {
    auto [it, inserted] = id.try_emplace(v, static_cast<int>(nodes.size()));
    if (inserted) nodes.emplace_back(v->point().x(), v->point().y());
    return it->second;
  };
  std::map<int, int> next;  // boundary: node -> following node counter-clockwise
  for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f) {
    if (!f->is_in_domain()) continue;
    std::array<int, 3> t{node_of(f->vertex(0)), node_of(f->vertex(1)), node_of(f->vertex(2))};
    tris.push_back(t);
    for (int i = 0; i < 3; ++i) {
      auto nb = f->neighbor(i);
      if (cdt.is_infinite(nb) || !nb->is_in_domain()) next[t[(i + 1) % 3]] = t[(i + 2) % 3];
    }
  }
  std::vector<int> corners;
  for (size_t c : corner_pos) corners.push_back(id.at(vh[c]));
  std::vector<int> loop{corners[0]};
  while (true) {
    auto it = next.find(loop.back());
    if (it == next.end()) throw std::logic_error("mesh_polygon: open boundary");
    if (it->second == loop.front()) break;
    loop.push_back(it->second);
    if (loop.size() > next.size()) throw std::logic_error("mesh_polygon: boundary does not close");
  }
  if (loop.size() != next.size()) throw std::logic_error("mesh_polygon: boundary has several loops");
  return renumber_boundary_first(nodes, tris, loop, corners);
}

TriMesh mesh_rectangle(double x0, double y0, double w, double h, int nx, int ny, RectPattern pattern) {
  if (!(w > 0.0) || !(h > 0.0) || nx < 1 || ny < 1)
    throw InputError("mesh_rectangle: needs positive width and height and at least one cell each way");
  std::vector<Vec2> nodes;
  auto grid = [&](int i, int j) { return j * (nx + 1) + i; };
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i)
      nodes.emplace_back(x0 + w * i / nx, y0 + h * j / ny);
  std::vector<std::array<int, 3>> tris;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const int a = grid(i, j), b = grid(i + 1, j), c = grid(i + 1, j + 1), d = grid(i, j + 1);
      const bool along_ac = pattern == RectPattern::regular || (i + j) % 2 == 0;
      if (pattern == RectPattern::crossed) {
        const int e = static_cast<int>(nodes.size());
        nodes.push_back(0.25 * (nodes[a] + nodes[b] + nodes[c] + nodes[d]));
        tris.push_back({a, b, e});
        tris.push_back({b, c, e});
        tris.push_back({c, d, e});
        tris.push_back({d, a, e});
      } else if (along_ac) {
        tris.push_back({a, b, c});
        tris.push_back({a, c, d});
      } else {
        tris.push_back({a, b, d});
        tris.push_back({b, c, d});
      }
    }
  std::vector<int> loop;
  for (int i = 0; i < nx; ++i) loop.push_back(grid(i, 0));
  for (int j = 0; j < ny; ++j) loop.push_back(grid(nx, j));
  for (int i = nx; i > 0; --i) loop.push_back(grid(i, ny));
  for (int j = ny; j > 0; --j) loop.push_back(grid(0, j));
  const std::vector<int> corners{grid(0, 0), grid(nx, 0), grid(nx, ny), grid(0, ny)};
  return renumber_boundary_first(nodes, tris, loop, corners);
}

MeshQuality mesh_quality(const TriMesh& m) {
  MeshQuality q;
  q.min_angle_deg = 180.0;
  q.min_edge = std::numeric_limits<double>::infinity();
  q.min_zone_area = std::numeric_limits<double>::infinity();
  for (const auto& t : m.triangles) {
    const Vec2 p[3] = {m.nodes[t[0]], m.nodes[t[1]], m.nodes[t[2]]};
    const double a = 0.5 * cross(p[1] - p[0], p[2] - p[0]);
    q.area += a;
    q.min_zone_area = std::min(q.min_zone_area, a);
    for (int i = 0; i < 3; ++i) {
      const Vec2 u = p[(i + 1) % 3] - p[i], v = p[(i + 2) % 3] - p[i];
      q.max_edge = std::max(q.max_edge, u.norm());
      q.min_edge = std::min(q.min_edge, u.norm());
      const double ang = std::atan2(std::abs(cross(u, v)), u.dot(v)) * 180.0 / std::numbers::pi;
      q.min_angle_deg = std::min(q.min_angle_deg, ang);
    }
  }
  return q;
}

}  // namespace rockdem
