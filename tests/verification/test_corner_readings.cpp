// Contact geometry past the end of an edge and where a face bends, the readings behind the drift
// study's kick and its static stages that did not settle (issue 14; docs/engine.md, narrow phase):
//  - a corner beside the face of a sharp wedge, just below the wedge's tip, is as far from the
//    wedge as that face: it used to be read as touching it, measured from the other face past the
//    tip along the tip's mean normal (a 22-degree tip, a corner 32 mm beside its face read 4 mm
//    deep, and a block was kicked off at 23 m/s);
//  - a point beyond the corner of a block whose face has flat vertices, on the line of that face,
//    is not in contact with it: the face used to run on past the block along that line;
//  - a corner sliding across a vertex where the other block's face bends by 15 degrees sees its
//    normal turn gradually, and one held just outside that vertex keeps its edge and normal from
//    step to step: its normal used to turn by the whole bend at once, and in the wedge outside the
//    vertex the contact went from one edge to the other and back at every step.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <numbers>
#include <string>
#include <vector>

#include "framework/contact/detection.hpp"
#include "framework/io/case.hpp"
#include "framework/simulation/run_case.hpp"
#include "polygon_case.hpp"

using namespace rockdem;
using polygon_case::block;
using polygon_case::contacts_of;
using polygon_case::place;

namespace {

// Rounding 1 mm, detection distance 2 mm.
const std::string kHeader =
    "title = \"corner readings\"\n[model]\nrounding = \"1 mm\"\ndetection_tolerance = \"1 mm\"\n"
    "[[joints]]\nname = \"j\"\nlaw = \"coulomb_slip\"\nbetween = [\"*\", \"*\"]\nkn = \"10 GPa/m\"\nks = \"10 GPa/m\"\n"
    "friction = \"30 deg\"\n";

double degrees(const Vec2& a, const Vec2& b) { return std::atan2(cross(a, b), a.dot(b)) * 180.0 / std::numbers::pi; }

}  // namespace

TEST(CornerReadings, CornerBesideAWedgeTipIsAsFarAsTheFace) {
  // A 22-degree wedge standing on its base, tip at (0, 1); a 0.1 m square whose bottom-left corner
  // (its point 0) is 1.5 mm below the tip's height and 32 mm from the wedge's right face.
  const double half = 11.0 * std::numbers::pi / 180.0, h = 1.0, below = 0.0015, beside = 0.032;
  const double base = h * std::tan(half);
  Case c = load_case_text(kHeader + polygon_case::rigid_block("wedge", {{-base, 0}, {base, 0}, {0, h}}) +
                              polygon_case::rigid_block("sq", {{0.5, 0.5}, {0.6, 0.5}, {0.6, 0.6}, {0.5, 0.6}}) + polygon_case::kOneStep,
                          "wedge", ".");
  // The right face's outward normal (cos 11, sin 11); the corner at that distance from the face.
  const Vec2 n(std::cos(half), std::sin(half));
  const double y = h - below, x_face = below * std::tan(half);
  const Vec2 corner(x_face + beside / n.x(), y);
  place(c, "sq", 0, corner);
  const double to_face = (corner - Vec2(0, h)).dot(n);
  ASSERT_NEAR(to_face, beside, 1e-12);
  detect_contacts(c.model, c.settings.detection);
  for (const Contact* k : contacts_of(c, "sq", 0, "wedge"))
    ADD_FAILURE() << "the corner 32 mm beside the wedge's face has a contact on it, overlap " << k->overlap * 1e3
                  << " mm, normal (" << k->normal.transpose() << ")";
  // Within the detection distance of the face it touches the face, with the face's normal.
  place(c, "sq", 0, Vec2(x_face + 0.0015 / n.x(), y));
  detect_contacts(c.model, c.settings.detection);
  const auto near = contacts_of(c, "sq", 0, "wedge");
  ASSERT_EQ(near.size(), 1u);
  EXPECT_NEAR(near[0]->overlap, -0.0015, 1e-6);
  EXPECT_LT(std::abs(degrees(near[0]->normal, n)), 0.5);
}

TEST(CornerReadings, NoContactBeyondTheCornerOfAFaceWithFlatVertices) {
  // A block whose top face y = 0 has flat vertices every 0.25 m, its right corner at (1, 0); a
  // 0.1 m square 0.2 m beyond that corner whose bottom-left corner is 0.5 mm below the face's
  // line (and 0.5 m above the block's lower step), and another whose corner is 0.5 mm into the
  // face.
  // The block steps down to y = -0.5 beyond that corner and runs on to x = 2, so that the square
  // is inside its bounding box (the broad phase skips points outside it). The outline starts on
  // the face, so that its flat stretch is measured first (the search keeps the nearest reading so
  // far and skips edges farther than that).
  const std::vector<Vec2> pts = {{0.75, 0}, {0.5, 0}, {0.25, 0}, {0, 0}, {0, -1}, {2, -1}, {2, -0.5}, {1, -0.5}, {1, 0}};
  Case c = load_case_text(kHeader + polygon_case::rigid_block("base", pts) + polygon_case::rigid_block("far", {{2, 2}, {2.1, 2}, {2.1, 2.1}, {2, 2.1}}) +
                              polygon_case::rigid_block("on", {{3, 3}, {3.1, 3}, {3.1, 3.1}, {3, 3.1}}) + polygon_case::kOneStep,
                          "flat_vertices", ".");
  place(c, "far", 0, Vec2(1.2, -0.0005));
  place(c, "on", 0, Vec2(0.4, -0.0005));
  detect_contacts(c.model, c.settings.detection);
  for (int k = 0; k < 4; ++k)
    for (const Contact* ct : contacts_of(c, "far", k, "base"))
      ADD_FAILURE() << "point " << k << " of the square 0.2 m beyond the corner has a contact on the base, overlap "
                    << ct->overlap * 1e3 << " mm";
  const auto on = contacts_of(c, "on", 0, "base");
  ASSERT_EQ(on.size(), 1u);
  EXPECT_NEAR(on[0]->overlap, 0.0005, 1e-9);
  EXPECT_NEAR(on[0]->normal.y(), 1.0, 1e-12);
}

namespace {

// A base whose top face runs level to (0, 0) and then falls at 15 degrees (a convex vertex, as
// each of a drift opening's 24 vertices is), and a 0.1 m square over it whose bottom-left corner
// (point 0) is placed by the caller.
Case bend_case() {
  const double t = std::tan(15.0 * std::numbers::pi / 180.0);
  return load_case_text(kHeader + polygon_case::rigid_block("base", {{-1, -1}, {1, -1}, {1, -t}, {0, 0}, {-1, 0}}) +
                            polygon_case::rigid_block("sq", {{2, 2}, {2.1, 2}, {2.1, 2.1}, {2, 2.1}}) + polygon_case::kOneStep,
                        "bend", ".");
}

}  // namespace

TEST(CornerReadings, NormalTurnsGraduallyWhereTheFaceBends) {
  Case c = bend_case();
  const double bend = 15.0 * std::numbers::pi / 180.0, t = std::tan(bend);
  const Vec2 level(0, 1), falling(std::sin(bend), std::cos(bend));
  // The corner 0.3 mm into the surface below it, from 3 mm before the vertex to 3 mm after, a
  // fresh detection at each position.
  double largest_jump = 0.0, last = 0.0;
  bool first = true;
  for (int i = -30; i <= 30; ++i) {
    const double x = 1e-4 * i, surface = x < 0.0 ? 0.0 : -x * t;
    place(c, "sq", 0, Vec2(x, surface - 0.0003));
    detect_contacts(c.model, c.settings.detection);
    const auto found = contacts_of(c, "sq", 0, "base");
    ASSERT_EQ(found.size(), 1u) << "at x = " << x;
    const double angle = degrees(level, found[0]->normal);
    if (!first) largest_jump = std::max(largest_jump, std::abs(angle - last));
    if (i == -30) {
      EXPECT_NEAR(angle, 0.0, 1e-9);
    }
    if (i == 0) {
      EXPECT_NEAR(angle, -7.5, 1.0) << "at the vertex, half way (-8.09 measured: the edge after it, by its own coordinate)";
    }
    if (i == 30) {
      EXPECT_NEAR(degrees(falling, found[0]->normal), 0.0, 1e-9);
    }
    EXPECT_GT(found[0]->overlap, 0.0) << "at x = " << x;
    last = angle;
    first = false;
  }
  // 15 degrees over the 2 mm either side of the vertex, 0.75 degrees per 0.1 mm, but where the
  // weight's coordinate changes: it is measured along the edge the contact is on, so at the
  // window's start and where the point changes edge (at 0.3 mm deep, 0.08 mm apart along the two
  // edges) it turns by up to 1.34 degrees (measured); before, by the whole 15 at once.
  std::cout << "normal across a 15-degree bend: largest turn between positions 0.1 mm apart " << largest_jump << " deg\n";
  EXPECT_LT(largest_jump, 1.5);
}

TEST(CornerReadings, ContactOutsideAConvexVertexKeepsItsEdge) {
  // The corner held 0.1 mm past the vertex and 0.8 mm above it, in the wedge outside both edges
  // (past the level edge's end, and above the line through the vertex along the falling edge's
  // normal): the per-step update keeps the contact on one edge with one normal.
  Case c = bend_case();
  const Vec2 held(0.0001, 0.0008);
  const double bend = 15.0 * std::numbers::pi / 180.0;
  ASSERT_GT(held.y(), held.x() / std::tan(bend));
  place(c, "sq", 0, held);
  detect_contacts(c.model, c.settings.detection);
  const auto found = contacts_of(c, "sq", 0, "base");
  ASSERT_EQ(found.size(), 1u);
  const int edge = found[0]->edge;
  const Vec2 normal = found[0]->normal;
  for (int step = 0; step < 6; ++step) {
    update_contact_geometry(c.model);
    const auto now = contacts_of(c, "sq", 0, "base");
    ASSERT_EQ(now.size(), 1u);
    EXPECT_EQ(now[0]->edge, edge) << "step " << step;
    EXPECT_LT((now[0]->normal - normal).norm(), 1e-12) << "step " << step;
  }
}
