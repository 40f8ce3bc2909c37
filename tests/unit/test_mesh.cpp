#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <map>
#include <random>
#include <utility>

#include "framework/core/error.hpp"
#include "framework/geometry/mesh.hpp"

using namespace rockdem;

namespace {

double dist_to_segment(const Vec2& q, const Vec2& a, const Vec2& b) {
  const Vec2 ab = b - a;
  const double t = std::clamp((q - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
  return (a + t * ab - q).norm();
}

// Checks every structural promise of TriMesh against the polygon it meshes (CCW polygon).
void expect_valid_mesh(const TriMesh& m, const Polygon& poly_ccw, double max_boundary_edge) {
  const double scale = std::sqrt(std::abs(signed_area(poly_ccw)));
  // Zones counter-clockwise, areas sum to the polygon's area.
  double area = 0.0;
  for (const auto& t : m.triangles) {
    const double a = 0.5 * cross(m.nodes[t[1]] - m.nodes[t[0]], m.nodes[t[2]] - m.nodes[t[0]]);
    EXPECT_GT(a, 0.0);
    area += a;
  }
  EXPECT_NEAR(area, signed_area(poly_ccw), 1e-12 * scale * scale);
  // Watertight: interior edges shared by two zones in opposite directions; the edges used once
  // are exactly the boundary loop's edges, in its direction.
  std::map<std::pair<int, int>, int> directed;
  for (const auto& t : m.triangles)
    for (int i = 0; i < 3; ++i) ++directed[{t[i], t[(i + 1) % 3]}];
  std::map<std::pair<int, int>, int> once;
  for (const auto& [e, n] : directed) {
    EXPECT_EQ(n, 1) << "edge used twice in the same direction";
    if (!directed.count({e.second, e.first})) once[e] = 1;
  }
  const size_t nb = m.boundary.size();
  ASSERT_EQ(once.size(), nb);
  for (size_t i = 0; i < nb; ++i) {
    EXPECT_EQ(m.boundary[i], static_cast<int>(i));  // boundary nodes first, in loop order
    const int a = m.boundary[i], b = m.boundary[(i + 1) % nb];
    EXPECT_TRUE(once.count({a, b})) << "boundary loop edge " << a << "-" << b << " is not a free zone edge";
    EXPECT_LE((m.nodes[b] - m.nodes[a]).norm(), max_boundary_edge * (1 + 1e-9));
  }
  // The loop starts at the polygon's first vertex, visits the corners in order, and every
  // boundary node lies on the polygon outline.
  ASSERT_EQ(m.corners.size(), poly_ccw.size());
  EXPECT_EQ(m.corners[0], m.boundary[0]);
  for (size_t c = 0; c < poly_ccw.size(); ++c) {
    EXPECT_NEAR((m.nodes[m.corners[c]] - poly_ccw[c]).norm(), 0.0, 1e-14 * scale);
    if (c > 0) {
      EXPECT_GT(m.corners[c], m.corners[c - 1]);
    }
  }
  Polygon loop;
  for (int v : m.boundary) {
    loop.push_back(m.nodes[v]);
    double d = 1e300;
    for (size_t e = 0; e < poly_ccw.size(); ++e)
      d = std::min(d, dist_to_segment(m.nodes[v], poly_ccw[e], poly_ccw[(e + 1) % poly_ccw.size()]));
    EXPECT_LT(d, 1e-12 * scale);
  }
  EXPECT_NEAR(signed_area(loop), signed_area(poly_ccw), 1e-12 * scale * scale);
  // Interior nodes strictly inside.
  for (size_t v = nb; v < m.nodes.size(); ++v)
    EXPECT_EQ(locate_point(m.nodes[v], poly_ccw), PointLocation::inside);
}

}  // namespace

TEST(Mesh, DirectShearTopBlockUnstructured) {
  const Polygon top{{0.051, 0.102}, {0.254, 0.102}, {0.254, 0.204}, {0.051, 0.204}};
  const double h = 0.01;
  const TriMesh m = mesh_polygon(top, h);
  expect_valid_mesh(m, top, h);
  const MeshQuality q = mesh_quality(m);
  // Refinement that keeps the boundary spacing (see mesh.hpp): measured 27.6 degrees, longest
  // edge 1.22 h; the bounds leave room for CGAL versions without inviting slivers.
  EXPECT_GE(q.min_angle_deg, 20.0);
  EXPECT_LE(q.max_edge, 1.5 * h);
  EXPECT_GT(q.min_edge, 0.25 * h);  // refinement stops near zone_size, not far below it
  // The 0.203 m faces are split evenly into 21 segments of 9.67 mm, the 0.102 m faces into 11.
  EXPECT_EQ(m.boundary.size(), 2u * (21 + 11));
  for (int i = 0; i < 21; ++i)
    EXPECT_NEAR((m.nodes[i + 1] - m.nodes[i]).norm(), 0.203 / 21, 1e-12);
  std::cout << "[          ] top block: " << m.nodes.size() << " gridpoints, " << m.triangles.size()
            << " zones, min angle " << q.min_angle_deg << " deg\n";
}

TEST(Mesh, NonConvexClockwisePolygon) {
  // An L-shaped block given clockwise: the mesh is counter-clockwise, first vertex first.
  Polygon ell_cw{{0, 0}, {0, 2}, {1, 2}, {1, 1}, {2, 1}, {2, 0}};
  const TriMesh m = mesh_polygon(ell_cw, 0.3);
  Polygon ccw = ell_cw;
  make_ccw(ccw);
  expect_valid_mesh(m, ccw, 0.3);
  EXPECT_GE(mesh_quality(m).min_angle_deg, 20.0);
  // A sharp 30-degree wedge still meshes (the angle bound cannot hold at a sharper input corner).
  const Polygon wedge{{0, 0}, {1, 0}, {std::cos(M_PI / 6), std::sin(M_PI / 6)}};
  const TriMesh w = mesh_polygon(wedge, 0.1);
  expect_valid_mesh(w, wedge, 0.1);
}

TEST(Mesh, RejectsBadInput) {
  const Polygon sq{{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  EXPECT_THROW(mesh_polygon(sq, 0.0), InputError);
  EXPECT_THROW(mesh_polygon(sq, -1.0), InputError);
  EXPECT_THROW(mesh_polygon({{0, 0}, {1, 1}, {1, 0}, {0, 1}}, 0.1), InputError);
  EXPECT_THROW(mesh_rectangle(0, 0, 1, 1, 0, 3), InputError);
  EXPECT_THROW(mesh_rectangle(0, 0, -1, 1, 2, 3), InputError);
}

TEST(Mesh, StructuredRectanglePatterns) {
  const double x0 = 0.051, y0 = 0.102, w = 0.203, h = 0.102;
  const Polygon r{{x0, y0}, {x0 + w, y0}, {x0 + w, y0 + h}, {x0, y0 + h}};
  for (auto pat : {RectPattern::regular, RectPattern::alternating, RectPattern::crossed}) {
    const TriMesh m = mesh_rectangle(x0, y0, w, h, 20, 10, pat);
    expect_valid_mesh(m, r, std::max(w / 20, h / 10));
    const size_t per_cell = pat == RectPattern::crossed ? 4 : 2;
    EXPECT_EQ(m.triangles.size(), per_cell * 200);
    EXPECT_EQ(m.boundary.size(), 60u);
    EXPECT_EQ(m.nodes.size(), 21u * 11 + (pat == RectPattern::crossed ? 200 : 0));
    // Evenly spaced bottom face gridpoints.
    for (int i = 0; i < 20; ++i) EXPECT_NEAR(m.nodes[i + 1].x() - m.nodes[i].x(), w / 20, 1e-15);
    const MeshQuality q = mesh_quality(m);
    EXPECT_GT(q.min_angle_deg, 44.8);  // nearly square cells (10.15 mm x 10.2 mm)
  }
  // Alternating diagonals: each node of the interior grid is shared by 4 or 8 zones, so the mesh
  // is symmetric about the rectangle's mid-lines; check the count of zones touching each corner.
  const TriMesh a = mesh_rectangle(0, 0, 2, 2, 2, 2, RectPattern::alternating);
  std::vector<int> deg(a.nodes.size(), 0);
  for (const auto& t : a.triangles)
    for (int v : t) ++deg[v];
  for (int c : a.corners) EXPECT_EQ(deg[c], 2);  // (i+j) even at all four corners
}

TEST(Mesh, RandomStarShapedPolygons) {
  // 150 random star-shaped outlines (3-14 vertices, either orientation, far from the origin) with
  // random zone sizes: every mesh is valid, and no zone angle is below 20 degrees unless an input
  // corner is sharper than that (no mesher can do better there).
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  int meshed = 0;
  for (int k = 0; k < 150; ++k) {
    const int n = 3 + static_cast<int>(rng() % 12);
    std::vector<double> ang;
    for (int i = 0; i < n; ++i) ang.push_back(2 * M_PI * u(rng));
    std::sort(ang.begin(), ang.end());
    Polygon p;
    for (int i = 0; i < n; ++i) {
      const double r = 10.0 * (0.3 + u(rng));
      p.push_back(Vec2(100.0 + r * std::cos(ang[i]), -50.0 + r * std::sin(ang[i])));
    }
    if (!is_simple(p)) continue;
    if (k % 2) std::reverse(p.begin(), p.end());
    const double h = 10.0 * (0.05 + 0.3 * u(rng));
    const TriMesh m = mesh_polygon(p, h);
    Polygon ccw = p;
    make_ccw(ccw);
    expect_valid_mesh(m, ccw, h);
    double sharpest = 180.0;
    for (size_t i = 0; i < ccw.size(); ++i) {
      const Vec2 a = ccw[(i + ccw.size() - 1) % ccw.size()] - ccw[i], b = ccw[(i + 1) % ccw.size()] - ccw[i];
      sharpest = std::min(sharpest, std::atan2(std::abs(cross(a, b)), a.dot(b)) * 180.0 / M_PI);
    }
    EXPECT_GE(mesh_quality(m).min_angle_deg, std::min(20.0, sharpest - 1e-9)) << "polygon " << k;
    ++meshed;
  }
  EXPECT_GT(meshed, 100);
}
