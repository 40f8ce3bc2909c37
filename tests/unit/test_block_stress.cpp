// The mean stress of a block (framework/mechanics/block_stress.hpp) against closed forms: a
// uniform stress put on a rigid polygon's boundary as the tractions sigma . n, lumped half to each
// end of every edge as the engine lumps boundary forces, comes back exactly, for a convex and a
// concave (L-shaped) block, rotated; a deformable block gives its zones' area-weighted mean.
// (Through the whole engine: test_shared_corners.cpp, the rigid equal-width stack.)
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "framework/mechanics/block_stress.hpp"
#include "framework/model/model.hpp"

using namespace rockdem;

namespace {

// A rigid block of the polygon `pts` (counter-clockwise), its centroid filled in, and on its
// gridpoints the forces of the uniform stress s (sxx, syy, sxy).
Model rigid_block_under(const std::vector<Vec2>& pts, const Voigt3& s) {
  Model m;
  Block b;
  b.rigid = true;
  b.n_gp = static_cast<int>(pts.size());
  double a = 0.0;
  Vec2 c = Vec2::Zero();
  for (std::size_t i = 0; i < pts.size(); ++i) {
    GridPoint g;
    g.x0 = g.x = pts[i];
    m.gp.push_back(g);
    b.boundary.push_back(static_cast<int>(i));
    const Vec2& p = pts[i];
    const Vec2& q = pts[(i + 1) % pts.size()];
    a += 0.5 * cross(p, q);
    c += cross(p, q) * (p + q) / 6.0;
  }
  b.xc = b.xc0 = c / a;
  m.blocks.push_back(b);
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const std::size_t j = (i + 1) % pts.size();
    const Vec2 e = pts[j] - pts[i];
    const Vec2 n(e.y(), -e.x());  // outward normal times the edge's length (counter-clockwise loop)
    const Vec2 t(s[0] * n.x() + s[2] * n.y(), s[2] * n.x() + s[1] * n.y());
    m.gp[i].f += 0.5 * t;
    m.gp[j].f += 0.5 * t;
  }
  return m;
}

std::vector<Vec2> rotated(std::vector<Vec2> pts, double angle, const Vec2& shift) {
  const double c = std::cos(angle), s = std::sin(angle);
  for (Vec2& p : pts) p = Vec2(c * p.x() - s * p.y(), s * p.x() + c * p.y()) + shift;
  return pts;
}

void expect_stress(const Voigt3& got, const Voigt3& want) {
  const double scale = want.cwiseAbs().maxCoeff();
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(got[k], want[k], 1e-12 * scale) << "component " << k;
}

}  // namespace

TEST(BlockStress, UniformStressOnAConvexRigidBlockComesBack) {
  const Voigt3 s(-3e6, -7e6, 1.5e6);
  const std::vector<Vec2> pentagon = {{0, 0}, {2, 0}, {2.5, 1.2}, {1, 2}, {-0.4, 1}};
  const Model m = rigid_block_under(rotated(pentagon, 0.37, Vec2(10, -4)), s);
  expect_stress(block_mean_stress(m)[0], s);
}

TEST(BlockStress, UniformStressOnAConcaveRigidBlockComesBack) {
  const Voigt3 s(2e5, -9e6, -4e6);
  const std::vector<Vec2> ell = {{0, 0}, {3, 0}, {3, 1}, {1, 1}, {1, 2.5}, {0, 2.5}};
  const Model m = rigid_block_under(rotated(ell, -1.1, Vec2(-2, 5)), s);
  expect_stress(block_mean_stress(m)[0], s);
}

TEST(BlockStress, PureShearAndNoForceGiveThemselves) {
  const std::vector<Vec2> square = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  expect_stress(block_mean_stress(rigid_block_under(square, Voigt3(0, 0, 2e6)))[0], Voigt3(0, 0, 2e6));
  EXPECT_EQ(block_mean_stress(rigid_block_under(square, Voigt3::Zero()))[0], Voigt3::Zero());
}

TEST(BlockStress, DeformableBlockIsItsZonesAreaWeightedMean) {
  Model m;
  Block b;
  b.rigid = false;
  b.first_zone = 0;
  b.n_zone = 2;
  m.blocks.push_back(b);
  Zone z0, z1;
  z0.area = 1.0;
  z0.stress = Voigt3(-1e6, -2e6, 0.0);
  z1.area = 3.0;
  z1.stress = Voigt3(-5e6, 2e6, 4e6);
  m.zones = {z0, z1};
  expect_stress(block_mean_stress(m)[0], Voigt3(-4e6, 1e6, 3e6));
}

TEST(BlockStress, HeldRigidBlockHasNoKnownStress) {
  // Its support's reactions are no forces of the model: NaN, not a number made from half the loads.
  const std::vector<Vec2> square = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  Model fixed = rigid_block_under(square, Voigt3(-1e6, -1e6, 0));
  fixed.blocks[0].fixed = true;
  EXPECT_FALSE(block_stress_known(fixed.blocks[0]));
  EXPECT_TRUE(block_mean_stress(fixed)[0].array().isNaN().all());
  Model driven = rigid_block_under(square, Voigt3(-1e6, -1e6, 0));
  driven.blocks[0].prescribed = Block::kDriveX;
  EXPECT_TRUE(block_mean_stress(driven)[0].array().isNaN().all());
}
