#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "framework/geometry/polygon.hpp"

using namespace rockdem;

namespace {
Polygon rect(double x0, double y0, double w, double h) { return {{x0, y0}, {x0 + w, y0}, {x0 + w, y0 + h}, {x0, y0 + h}}; }
Polygon reversed(Polygon p) {
  std::reverse(p.begin() + 1, p.end());
  return p;
}
// An L-shaped (non-convex) hexagon: the 2x2 square minus its upper-right unit square.
Polygon ell() { return {{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}}; }
}  // namespace

TEST(Polygon, AreaCentroidAndMomentsOfARectangle) {
  // Far from the origin on purpose: the sums are taken relative to the first vertex. (The input
  // coordinates themselves carry ~2e-12 m of rounding at 1e4 m; shoelace sums about the origin
  // would lose ~1e-8 m^2.)
  const double x0 = 1e4, y0 = -2e4, w = 0.305, h = 0.102;
  const Polygon r = rect(x0, y0, w, h);
  EXPECT_NEAR(signed_area(r), w * h, 1e-10 * w * h);
  EXPECT_NEAR(signed_area(reversed(r)), -w * h, 1e-10 * w * h);
  const Vec2 c = polygon_centroid(r);
  EXPECT_NEAR(c.x(), x0 + w / 2, 1e-10);
  EXPECT_NEAR(c.y(), y0 + h / 2, 1e-10);
  const SecondMoments m = second_moments(r);
  // b h^3 / 12 about the centroidal axes (e.g. Gere, Mechanics of Materials, App. D).
  EXPECT_NEAR(m.ixx, w * h * h * h / 12, 1e-9 * w * h * h * h / 12);
  EXPECT_NEAR(m.iyy, h * w * w * w / 12, 1e-9 * h * w * w * w / 12);
  EXPECT_NEAR(m.ixy, 0.0, 1e-12);
  const SecondMoments mr = second_moments(reversed(r));
  EXPECT_NEAR(mr.polar(), m.polar(), 1e-9 * m.polar());
}

TEST(Polygon, MomentsOfARightTriangleAndAnLShape) {
  // Right triangle with legs b (x) and h (y): Ixx = b h^3/36, Iyy = h b^3/36, Ixy = -b^2 h^2/72.
  const double b = 3.0, h = 2.0;
  const SecondMoments t = second_moments({{0, 0}, {b, 0}, {0, h}});
  EXPECT_NEAR(t.ixx, b * h * h * h / 36, 1e-12);
  EXPECT_NEAR(t.iyy, h * b * b * b / 36, 1e-12);
  EXPECT_NEAR(t.ixy, -b * b * h * h / 72, 1e-12);
  // L shape = three unit squares; centroid (5/6, 5/6); parallel-axis sum over the squares.
  const Polygon l = ell();
  EXPECT_NEAR(signed_area(l), 3.0, 1e-14);
  EXPECT_NEAR(polygon_centroid(l).x(), 5.0 / 6, 1e-14);
  EXPECT_NEAR(polygon_centroid(l).y(), 5.0 / 6, 1e-14);
  double ixx = 0.0;
  for (double cy : {0.5, 0.5, 1.5}) ixx += 1.0 / 12 + (cy - 5.0 / 6) * (cy - 5.0 / 6);
  EXPECT_NEAR(second_moments(l).ixx, ixx, 1e-13);
}

TEST(Polygon, OrientationConvexityAndSimplicity) {
  Polygon p = reversed(rect(0, 0, 2, 1));
  const Vec2 first = p[0];
  EXPECT_TRUE(make_ccw(p));
  EXPECT_EQ(p[0], first);
  EXPECT_GT(signed_area(p), 0.0);
  EXPECT_FALSE(make_ccw(p));

  EXPECT_TRUE(is_convex(rect(0, 0, 2, 1)));
  EXPECT_TRUE(is_convex(reversed(rect(0, 0, 2, 1))));
  EXPECT_FALSE(is_convex(ell()));
  EXPECT_TRUE(is_convex({{0, 0}, {1, 0}, {2, 0}, {2, 1}, {0, 1}}));  // collinear vertex allowed

  EXPECT_TRUE(is_simple(ell()));
  EXPECT_TRUE(is_simple(rect(0, 0, 1, 1)));
  EXPECT_FALSE(is_simple({{0, 0}, {1, 1}, {1, 0}, {0, 1}}));          // bow tie
  EXPECT_FALSE(is_simple({{0, 0}, {1, 0}, {1, 0}, {0, 1}}));          // repeated vertex
  EXPECT_FALSE(is_simple({{0, 0}, {1, 0}, {2, 0}}));                  // no area
  EXPECT_FALSE(is_simple({{0, 0}, {2, 0}, {1, 0}, {1, 1}}));          // folds back on an edge
  EXPECT_FALSE(is_simple({{0, 0}, {2, 0}, {2, 2}, {1, 0}, {0, 2}}));  // vertex touching an edge
}

TEST(Polygon, PointLocation) {
  const Polygon l = ell();
  EXPECT_EQ(locate_point({0.5, 0.5}, l), PointLocation::inside);
  EXPECT_EQ(locate_point({1.5, 1.5}, l), PointLocation::outside);  // the notch
  EXPECT_EQ(locate_point({1.5, 1.0}, l), PointLocation::boundary);
  EXPECT_EQ(locate_point({0.0, 0.0}, l), PointLocation::boundary);
  EXPECT_EQ(locate_point({1.5, 1.0 + 1e-9}, l, 1e-8), PointLocation::boundary);
  EXPECT_EQ(locate_point({1.5, 1.0 + 1e-6}, l, 1e-8), PointLocation::outside);
  EXPECT_EQ(locate_point({-0.1, 1.0}, l), PointLocation::outside);  // ray through a vertex
  EXPECT_EQ(locate_point({0.5, 1.0}, l), PointLocation::inside);    // same height as a vertex
  EXPECT_TRUE(point_in_polygon({0.5, 1.5}, reversed(l)));
}

TEST(Polygon, EarClippingCoversTheArea) {
  const Polygon l = ell();
  const auto tris = triangulate_polygon(l);
  double a = 0.0;
  for (const auto& t : tris) {
    const double at = 0.5 * cross(l[t[1]] - l[t[0]], l[t[2]] - l[t[0]]);
    EXPECT_GT(at, 0.0);
    a += at;
  }
  EXPECT_NEAR(a, 3.0, 1e-14);
  EXPECT_EQ(tris.size(), 4u);
  // A comb with many reflex corners, clockwise.
  Polygon comb{{0, 0}};
  for (int i = 0; i < 5; ++i) {
    comb.push_back({2.0 * i, 3.0});
    comb.push_back({2.0 * i + 1, 3.0});
    comb.push_back({2.0 * i + 1, 1.0});
    comb.push_back({2.0 * i + 2, 1.0});
  }
  comb.push_back({10.0, 0.0});
  comb = reversed(comb);  // now counter-clockwise? either way the triangles come out CCW
  double ac = 0.0;
  for (const auto& t : triangulate_polygon(comb)) ac += std::abs(0.5 * cross(comb[t[1]] - comb[t[0]], comb[t[2]] - comb[t[0]]));
  EXPECT_NEAR(ac, std::abs(signed_area(comb)), 1e-12);
}

TEST(Polygon, OverlapIsPositiveAreaNotEdgeContact) {
  const double tol = 1e-9;
  const Polygon bottom = rect(0, 0, 0.305, 0.102);
  const Polygon top = rect(0.051, 0.102, 0.203, 0.102);  // sits on the bottom block's top face
  EXPECT_NEAR(intersection_area(bottom, top), 0.0, 1e-15);
  EXPECT_FALSE(polygons_overlap(bottom, top, tol));
  EXPECT_FALSE(polygons_overlap(bottom, rect(0.305, 0.0, 0.1, 0.1), tol));  // side by side
  EXPECT_FALSE(polygons_overlap(bottom, rect(0.305, 0.102, 0.1, 0.1), tol));  // corner to corner
  EXPECT_FALSE(polygons_overlap(bottom, rect(1, 1, 1, 1), tol));              // apart

  // Pushed 1 mm into the bottom block: 0.203 m x 1 mm overlap.
  const Polygon pushed = rect(0.051, 0.101, 0.203, 0.102);
  EXPECT_NEAR(intersection_area(bottom, pushed), 0.203e-3, 1e-12);
  EXPECT_TRUE(polygons_overlap(bottom, pushed, tol));
  EXPECT_TRUE(polygons_overlap(bottom, reversed(pushed), tol));
  // Identical blocks, one inside the other, a corner poking in.
  EXPECT_TRUE(polygons_overlap(bottom, bottom, tol));
  EXPECT_TRUE(polygons_overlap(bottom, rect(0.1, 0.01, 0.01, 0.01), tol));
  EXPECT_TRUE(polygons_overlap(bottom, {{0.3, 0.1}, {0.4, 0.2}, {0.3, 0.3}, {0.2, 0.2}}, tol));
  // Non-convex: a square in the notch of the L touches it along two edges only.
  EXPECT_FALSE(polygons_overlap(ell(), rect(1, 1, 1, 1), tol));
  EXPECT_TRUE(polygons_overlap(ell(), rect(0.9, 0.9, 1, 1), tol));
  EXPECT_NEAR(intersection_area(ell(), rect(0.9, 0.9, 1, 1)), 0.1 * 1.0 + 0.1 * 0.9, 1e-14);
  // An overlap band thinner than tol counts as touching.
  EXPECT_FALSE(polygons_overlap(bottom, rect(0.051, 0.102 - 1e-10, 0.203, 0.102), tol));
}
