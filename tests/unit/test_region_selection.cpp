// Face and region selection for rock masses (framework/boundary/region.hpp): a named face is the
// block's outer face only, never an inner wall that faces the same way; a region takes the
// boundary gridpoints inside it across blocks.
#include <gtest/gtest.h>

#include "framework/boundary/region.hpp"
#include "framework/mechanics/zones.hpp"

using namespace rockdem;

namespace {

// A 4 m square with a notch 2 m deep and 2 m high cut from its right side: the notch's wall
// (x = 2) faces +x like the right face (x = 4), its floor (y = 1) faces +y like the top (y = 4).
Model notched() {
  Model m;
  add_rigid_block(m, {{0, 0}, {4, 0}, {4, 1}, {2, 1}, {2, 3}, {4, 3}, {4, 4}, {0, 4}}, 2650.0, "notched", 0);
  add_rigid_block(m, {{0, 4}, {4, 4}, {4, 5}, {0, 5}}, 2650.0, "cap", 0);
  return m;
}

std::vector<Vec2> points_of(const Model& m, const FaceSelection& s) {
  std::vector<Vec2> out;
  for (int g : s.points) out.push_back(m.gp[g].x);
  return out;
}

}  // namespace

TEST(RegionSelection, NamedFaceIsTheOuterFaceOnly) {
  const Model m = notched();
  const double tol = outer_face_tolerance(m, 0);
  // By normal alone the notch's wall comes with the right face; the outer face is x = 4 only.
  EXPECT_EQ(select_face(m, 0, {1, 0}).edges.size(), 3u);
  const FaceSelection right = select_outer_face(m, 0, {1, 0}, tol);
  ASSERT_EQ(right.edges.size(), 2u);
  for (const Vec2& x : points_of(m, right)) EXPECT_DOUBLE_EQ(x.x(), 4.0);
  const FaceSelection top = select_outer_face(m, 0, {0, 1}, tol);
  ASSERT_EQ(top.edges.size(), 1u);
  for (const Vec2& x : points_of(m, top)) EXPECT_DOUBLE_EQ(x.y(), 4.0);
  EXPECT_EQ(select_outer_face(m, 0, {0, 0}, tol).edges.size(), 8u);  // "all"
}

TEST(RegionSelection, BoxAndLineReachEveryBlockInThem) {
  const Model m = notched();
  Region line;
  line.from = {0, 0};
  line.to = {0, 5};
  line.tolerance = 1e-6;
  const auto sels = select_region(m, line);
  ASSERT_EQ(sels.size(), 2u);  // both blocks have their left face on x = 0
  EXPECT_EQ(sels[0].block, 0);
  EXPECT_EQ(sels[0].edges.size(), 1u);
  EXPECT_EQ(sels[1].block, 1);
  EXPECT_EQ(sels[1].edges.size(), 1u);
  Region box;
  box.box = std::array<double, 4>{1.9, 0.9, 4.1, 3.1};  // the notch's three walls, not the cap
  const auto inner = select_region(m, box);
  ASSERT_EQ(inner.size(), 1u);
  EXPECT_EQ(inner[0].points.size(), 4u);
  EXPECT_EQ(inner[0].edges.size(), 3u);
}
