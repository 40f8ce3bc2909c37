#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <limits>
#include <random>

#include "framework/core/error.hpp"
#include "framework/mechanics/zones.hpp"
#include "models/rock/elastic.hpp"

using namespace rockdem;

namespace {
void add_elastic(Model& m, double rho, double k, double g) {
  m.materials.push_back(std::make_unique<RockMaterialAdapter<ElasticRock>>(ElasticRock::Params{rho, k, g}));
}
}  // namespace

TEST(Zones, RigidBlockMassInertiaAndGridpoints) {
  Model m;
  // Loading block given clockwise: stored counter-clockwise, first vertex kept.
  const Polygon cw{{-0.05, 0.102}, {-0.05, 0.204}, {0.051, 0.204}, {0.051, 0.102}};
  const int id0 = add_rigid_block(m, cw, 2420.0, "loading", 3);
  const int id1 = add_rigid_block(m, {{0, 0}, {1, 0}, {0, 1}}, 1000.0, "tri", 0);
  EXPECT_EQ(id0, 0);
  EXPECT_EQ(id1, 1);
  const Block& b = m.blocks[0];
  EXPECT_TRUE(b.rigid);
  EXPECT_EQ(b.name, "loading");
  EXPECT_EQ(b.group, 3);
  const double w = 0.101, h = 0.102;
  EXPECT_NEAR(b.mass, 2420.0 * w * h, 1e-12);
  EXPECT_NEAR(b.inertia, 2420.0 * w * h * (w * w + h * h) / 12, 1e-15);
  EXPECT_NEAR(b.xc0.x(), 0.0005, 1e-15);
  EXPECT_NEAR(b.xc0.y(), 0.153, 1e-15);
  EXPECT_EQ(b.xc, b.xc0);
  ASSERT_EQ(b.n_gp, 4);
  ASSERT_EQ(b.boundary.size(), 4u);
  EXPECT_EQ(m.gp[b.boundary[0]].x, cw[0]);
  EXPECT_EQ(m.gp[b.boundary[1]].x, cw[3]);  // reversed order after the first vertex
  for (int i = 0; i < 4; ++i) {
    const GridPoint& g = m.gp[b.first_gp + i];
    EXPECT_EQ(g.block, 0);
    EXPECT_EQ(g.local, i);
    EXPECT_EQ(g.x, g.x0);
    EXPECT_EQ(b.rest_offsets[i], g.x0 - b.xc0);
  }
  // Triangle: I_c = m (a^2 + b^2 + c^2) / 36 for a triangle of mass m and sides a, b, c.
  const Block& t = m.blocks[1];
  EXPECT_NEAR(t.inertia, 500.0 * (1 + 1 + 2) / 36, 1e-12);
  EXPECT_EQ(m.gp[t.first_gp].block, 1);
  EXPECT_EQ(t.first_gp, 4);

  EXPECT_THROW(add_rigid_block(m, {{0, 0}, {1, 1}, {1, 0}, {0, 1}}, 1000.0, "bowtie", 0), InputError);
  EXPECT_THROW(add_rigid_block(m, cw, 0.0, "massless", 0), InputError);
  EXPECT_EQ(m.blocks.size(), 2u);
}

TEST(Zones, DeformableBlockLumpedMassesAndIds) {
  Model m;
  add_elastic(m, 2420.0, 21.443e9, 16.083e9);
  add_rigid_block(m, {{-1, 0}, {0, 0}, {0, 1}, {-1, 1}}, 2000.0, "first", 0);
  const Polygon ell{{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}};
  const TriMesh mesh = mesh_polygon(ell, 0.25);
  const int id = add_deformable_block(m, mesh, 0, "ell", 2);
  EXPECT_EQ(id, 1);
  const Block& b = m.blocks[1];
  EXPECT_FALSE(b.rigid);
  EXPECT_EQ(b.first_gp, 4);
  EXPECT_EQ(b.n_gp, static_cast<int>(mesh.nodes.size()));
  EXPECT_EQ(b.first_zone, 0);
  EXPECT_EQ(b.n_zone, static_cast<int>(mesh.triangles.size()));
  ASSERT_EQ(b.boundary.size(), mesh.boundary.size());
  for (size_t i = 0; i < mesh.boundary.size(); ++i) EXPECT_EQ(b.boundary[i], 4 + mesh.boundary[i]);
  double mass = 0.0;
  for (int i = b.first_gp; i < b.first_gp + b.n_gp; ++i) {
    mass += m.gp[i].mass;
    EXPECT_GT(m.gp[i].mass, 0.0);
    EXPECT_EQ(m.gp[i].block, 1);
    EXPECT_EQ(m.gp[i].local, i - b.first_gp);
  }
  EXPECT_NEAR(mass, 2420.0 * 3.0, 1e-9);
  EXPECT_NEAR(b.mass, 2420.0 * 3.0, 1e-9);
  // The zone sums reproduce the polygon's centroid and polar moment exactly (up to round-off).
  EXPECT_NEAR((b.xc0 - polygon_centroid(ell)).norm(), 0.0, 1e-13);
  EXPECT_NEAR(b.inertia, 2420.0 * second_moments(ell).polar(), 1e-9 * b.inertia);
  for (int z = 0; z < b.n_zone; ++z) EXPECT_GT(m.zones[z].area, 0.0);
  EXPECT_THROW(add_deformable_block(m, mesh, 5, "nomaterial", 0), InputError);
}

TEST(Zones, InvertedZoneIsReportedWithItsBlock) {
  Model m;
  add_elastic(m, 2420.0, 20e9, 10e9);
  add_deformable_block(m, mesh_rectangle(0, 0, 1, 1, 1, 1, RectPattern::regular), 0, "flip", 0);
  m.gp[m.zones[0].n[1]].x = Vec2(-1.0, -1.0);
  m.step = 42;
  try {
    zone_forces(m, 1e-6, 0.0);
    FAIL() << "inverted zone accepted";
  } catch (const InstabilityError& e) {
    const std::string s = e.what();
    EXPECT_NE(s.find("'flip'"), std::string::npos) << s;
    EXPECT_NE(s.find("step 42"), std::string::npos) << s;
  }
}

TEST(Zones, StiffnessEstimateBoundsTheCriticalTimeStep) {
  // Assemble the global stiffness K from zone_forces (column j = -f/du for a velocity of dof j
  // moving it by du = 1e-9 m, small enough that the mid-step geometry does not matter), find the highest frequency of M^-1 K, and compare the exact critical step 2/w_max
  // with the estimate 2 min sqrt(m/k) from zone_stiffness: it must be safe (<=) and not wasteful.
  Model m;
  add_elastic(m, 2420.0, 21.443e9, 16.083e9);
  add_deformable_block(m, mesh_polygon({{0, 0}, {1, -0.2}, {2.3, 0.4}, {2.0, 1.5}, {0.7, 1.9}}, 0.4), 0, "b", 0);
  const int n = static_cast<int>(m.gp.size());
  Eigen::MatrixXd k(2 * n, 2 * n);
  for (int j = 0; j < 2 * n; ++j) {
    Model probe;
    add_elastic(probe, 2420.0, 21.443e9, 16.083e9);
    probe.gp = m.gp;
    probe.zones = m.zones;
    probe.blocks = m.blocks;
    for (auto& g : probe.gp) g.v.setZero();
    const double du = 1e-9;
    probe.gp[j / 2].v[j % 2] = 1.0;
    zone_forces(probe, du, 0.0);
    for (int i = 0; i < n; ++i) {
      k(2 * i, j) = -probe.gp[i].f.x() / du;
      k(2 * i + 1, j) = -probe.gp[i].f.y() / du;
    }
  }
  EXPECT_LT((k - k.transpose()).cwiseAbs().maxCoeff(), 1e-6 * k.cwiseAbs().maxCoeff());
  Eigen::VectorXd minv_sqrt(2 * n);
  for (int i = 0; i < n; ++i) minv_sqrt[2 * i] = minv_sqrt[2 * i + 1] = 1.0 / std::sqrt(m.gp[i].mass);
  const Eigen::MatrixXd a = minv_sqrt.asDiagonal() * (0.5 * (k + k.transpose())) * minv_sqrt.asDiagonal();
  const Eigen::VectorXd lam = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(a).eigenvalues();  // ascending
  // A free block has exactly three zero-energy modes (two translations, one rotation): no
  // spurious mechanisms in the constant-strain zones.
  EXPECT_LT(std::abs(lam[0]), 1e-9 * lam[2 * n - 1]);
  EXPECT_LT(std::abs(lam[2]), 1e-9 * lam[2 * n - 1]);
  EXPECT_GT(lam[3], 1e-4 * lam[2 * n - 1]);
  const double w_max = std::sqrt(lam[2 * n - 1]);
  const double dt_exact = 2.0 / w_max;

  zone_stiffness(m);
  double dt_est = 1e300;
  for (const auto& g : m.gp) dt_est = std::min(dt_est, 2.0 * std::sqrt(g.mass / g.stiffness));
  std::cout << "[          ] critical dt exact " << dt_exact << " s, estimate " << dt_est << " s (ratio "
            << dt_est / dt_exact << ")\n";
  EXPECT_LE(dt_est, dt_exact);
  EXPECT_GE(dt_est, 0.3 * dt_exact);

  // Undamped central differences from random velocities: bounded at the estimate, unbounded
  // just above the exact limit.
  auto energy_growth = [&](double dt) {
    Model run;
    add_elastic(run, 2420.0, 21.443e9, 16.083e9);
    run.gp = m.gp;
    run.zones = m.zones;
    run.blocks = m.blocks;
    std::mt19937 rng(7);
    std::normal_distribution<double> nd;
    for (auto& g : run.gp) g.v = Vec2(nd(rng), nd(rng)) * 1e-3;
    auto ke = [&] {
      double e = 0.0;
      for (const auto& g : run.gp) e += 0.5 * g.mass * g.v.squaredNorm();
      return e;
    };
    const double e0 = ke();
    double emax = e0;
    for (int s = 0; s < 3000; ++s) {
      for (auto& g : run.gp) g.f.setZero();
      try {
        zone_forces(run, dt, 0.0);
      } catch (const InstabilityError&) {
        return std::numeric_limits<double>::infinity();  // a zone turned inside out: blown up
      }
      for (auto& g : run.gp) {
        g.v += g.f / g.mass * dt;
        g.x += g.v * dt;
      }
      emax = std::max(emax, ke());
    }
    return emax / e0;
  };
  EXPECT_LT(energy_growth(dt_est), 10.0);
  EXPECT_GT(energy_growth(1.05 * dt_exact), 1e6);
}
