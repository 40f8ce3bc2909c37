// Uniform-stress patch test for deformable blocks (Irons & Razzaque 1972; Zienkiewicz & Taylor,
// The Finite Element Method, vol. 1, ch. 10): a linear displacement field prescribed on an
// unstructured mesh must give the exact uniform stress in every zone, zero forces at interior
// gridpoints and, at boundary gridpoints, exactly the consistent load of the uniform traction.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "framework/geometry/mesh.hpp"
#include "framework/mechanics/zones.hpp"
#include "models/rock/elastic.hpp"

using namespace rockdem;

namespace {

constexpr double kK = 21.443e9, kG = 16.083e9;  // Table 4-1 rock matrix (direct-shear specimen)

Model patch_model(const Polygon& outline, double h) {
  Model m;
  m.materials.push_back(std::make_unique<RockMaterialAdapter<ElasticRock>>(ElasticRock::Params{2420.0, kK, kG}));
  add_deformable_block(m, mesh_polygon(outline, h), 0, "patch", 0);
  return m;
}

// An irregular convex hexagon: no symmetry for errors to hide behind.
const Polygon kOutline{{0.0, 0.0}, {1.0, -0.2}, {2.3, 0.4}, {2.0, 1.5}, {0.7, 1.9}, {-0.4, 1.0}};

}  // namespace

TEST(PatchTest, LinearFieldGivesExactUniformStress) {
  Model m = patch_model(kOutline, 0.25);
  const Block& b = m.blocks[0];
  ASSERT_GT(b.n_gp - static_cast<int>(b.boundary.size()), 20) << "need interior gridpoints";
  // u = A x + c (strain plus a rotation part and a translation), applied as one velocity step
  // of dt = 1 in the engine's order: positions first, then zone_forces.
  Eigen::Matrix2d a;
  a << 2.0e-4, -1.0e-4, 3.0e-4, -1.5e-4;
  const Vec2 c(1e-3, -2e-3);
  for (auto& g : m.gp) {
    g.v = a * g.x0 + c;
    g.x = g.x0 + g.v;
  }
  zone_forces(m, 1.0, 0.0);

  // Gradient of the same linear field on the mid-step configuration (I + A/2) x0 + c/2:
  // L = A (I + A/2)^-1; its symmetric part is the strain increment in every zone.
  const Eigen::Matrix2d l = a * (Eigen::Matrix2d::Identity() + 0.5 * a).inverse();
  const Voigt3 eps(l(0, 0), l(1, 1), l(0, 1) + l(1, 0));
  const Voigt3 sigma = plane_strain_elasticity(kK, kG) * eps;
  const double szz = (kK - 2 * kG / 3) * (eps[0] + eps[1]);
  const double s_scale = sigma.cwiseAbs().maxCoeff();
  for (const Zone& z : m.zones) {
    EXPECT_NEAR((z.stress - sigma).cwiseAbs().maxCoeff(), 0.0, 1e-12 * s_scale);
    EXPECT_NEAR(z.szz, szz, 1e-12 * s_scale);
    // Accumulated strain: the increment turned by the step's rotation angle.
    EXPECT_NEAR(z.strain[0] + z.strain[1], eps[0] + eps[1], 1e-15);
  }
  // Interior gridpoints: forces cancel to round-off (force scale: stress x zone size).
  const double f_scale = s_scale * 0.25;
  std::vector<bool> on_boundary(m.gp.size(), false);
  for (int i : b.boundary) on_boundary[i] = true;
  double worst_interior = 0.0;
  for (size_t i = 0; i < m.gp.size(); ++i)
    if (!on_boundary[i]) worst_interior = std::max(worst_interior, m.gp[i].f.norm());
  EXPECT_LT(worst_interior, 1e-12 * f_scale);
  std::cout << "[          ] max interior |f| / (sigma h) = " << worst_interior / f_scale << "\n";

  // Boundary gridpoints: f_i = sum over its two boundary edges of (sigma n) L / 2 (the internal
  // force is minus the load the zones need from outside: f = -t L/2 with t = sigma n).
  Eigen::Matrix2d s;
  s << sigma[0], sigma[2], sigma[2], sigma[1];
  const size_t nb = b.boundary.size();
  Vec2 total = Vec2::Zero();
  double moment = 0.0;
  for (size_t k = 0; k < nb; ++k) {
    const GridPoint& g = m.gp[b.boundary[k]];
    const Vec2 prev = m.gp[b.boundary[(k + nb - 1) % nb]].x, next = m.gp[b.boundary[(k + 1) % nb]].x;
    // Outward normal times length of a counter-clockwise edge p->q is (q - p) rotated -90 deg.
    auto nl = [](const Vec2& p, const Vec2& q) { return Vec2(q.y() - p.y(), -(q.x() - p.x())); };
    const Vec2 expected = -0.5 * s * (nl(prev, g.x) + nl(g.x, next));
    EXPECT_NEAR((g.f - expected).norm(), 0.0, 1e-12 * f_scale) << "boundary gridpoint " << k;
    total += g.f;
    moment += cross(g.x, g.f);
  }
  EXPECT_NEAR(total.norm(), 0.0, 1e-11 * f_scale);
  EXPECT_NEAR(moment, 0.0, 1e-11 * f_scale);
}

TEST(PatchTest, RayleighDampingStressIsNotAccumulated) {
  Model m = patch_model(kOutline, 0.4);
  Eigen::Matrix2d a;
  a << 1.0e-3, 0.5e-3, 0.2e-3, -2.0e-3;  // velocity gradient [1/s]
  for (auto& g : m.gp) g.v = a * g.x;
  const double beta = 1e-4;
  zone_forces(m, 0.0, beta);  // dt = 0: no strain increment, only the damping stress
  const Voigt3 rate(a(0, 0), a(1, 1), a(0, 1) + a(1, 0));
  const Voigt3 sd = beta * plane_strain_elasticity(kK, kG) * rate;
  Eigen::Matrix2d s;
  s << sd[0], sd[2], sd[2], sd[1];
  for (const Zone& z : m.zones) EXPECT_EQ(z.stress, Voigt3::Zero());
  const Block& b = m.blocks[0];
  const size_t nb = b.boundary.size();
  for (size_t k = 0; k < nb; ++k) {
    const GridPoint& g = m.gp[b.boundary[k]];
    const Vec2 prev = m.gp[b.boundary[(k + nb - 1) % nb]].x, next = m.gp[b.boundary[(k + 1) % nb]].x;
    const Vec2 nl = Vec2(next.y() - prev.y(), -(next.x() - prev.x()));  // sum of the two edges
    EXPECT_NEAR((g.f + 0.5 * s * nl).norm(), 0.0, 1e-12 * sd.norm());
  }
}

TEST(PatchTest, RigidRotationCarriesStressWithoutStraining) {
  // A pre-stressed block turned rigidly through 90 degrees in 900 steps: the current-configuration
  // B matrix sees no strain, and the spin correction turns the stress with the block, so sxx and
  // syy swap and sxy changes sign; gridpoint forces stay self-equilibrated. (With the initial-
  // configuration B, a rotation theta reads as a strain ~ (1 - cos theta): 100% at 90 degrees.)
  Model m = patch_model(kOutline, 0.4);
  Eigen::Matrix2d a;
  a << 1.0e-4, 0.3e-4, 0.3e-4, -0.5e-4;
  for (auto& g : m.gp) g.v = a * g.x;
  zone_forces(m, 0.0, 0.0);
  for (const Zone& z : m.zones) EXPECT_EQ(z.stress, Voigt3::Zero());  // dt = 0: no increment
  for (auto& g : m.gp) g.f.setZero();
  zone_forces(m, 1.0, 0.0);
  const Voigt3 s0 = m.zones[0].stress;
  const double sz0 = m.zones[0].szz;
  const Vec2 centre = m.blocks[0].xc0;
  const int n = 900;
  const double omega = 2.0, dt = (M_PI / 2) / (omega * n);
  const Eigen::Rotation2Dd r(omega * dt);
  for (int k = 0; k < n; ++k) {
    for (auto& g : m.gp) {
      const Vec2 rel = g.x - centre;
      g.v = (r * rel - rel) / dt;  // secant velocity of an exact rigid turn by omega dt
      g.x += g.v * dt;
      g.f.setZero();
    }
    zone_forces(m, dt, 0.0);
  }
  const Voigt3 expected(s0[1], s0[0], -s0[2]);
  for (const Zone& z : m.zones) {
    EXPECT_NEAR((z.stress - expected).cwiseAbs().maxCoeff(), 0.0, 1e-9 * s0.cwiseAbs().maxCoeff());
    EXPECT_NEAR(z.szz, sz0, 1e-9 * s0.cwiseAbs().maxCoeff());  // round-off of 900 steps
  }
  // The net force and moment on the block vanish (uniform stress, free block).
  Vec2 total = Vec2::Zero();
  for (const auto& g : m.gp) total += g.f;
  EXPECT_LT(total.norm(), 1e-9 * s0.norm());
}
