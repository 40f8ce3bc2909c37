// A deformable block relaxed by the engine (explicit central differences, local damping) under a
// uniform normal traction on its top face, on rollers at its base and left side: the exact
// plane-strain answer is uniform uniaxial stress sigma_yy = -q, sigma_xx = 0, sigma_zz = nu
// sigma_yy, and a top settlement q H (1 - nu^2) / E. Constant-strain zones represent it exactly,
// so the only error is the relaxation's: the test asks for 1e-4 of q and of the settlement.
#include <gtest/gtest.h>

#include <cmath>

#include "framework/boundary/conditions.hpp"
#include "framework/boundary/fixed_condition.hpp"
#include "framework/boundary/traction_condition.hpp"
#include "framework/mechanics/engine.hpp"
#include "framework/mechanics/zones.hpp"
#include "models/rock/elastic.hpp"

using namespace rockdem;

TEST(ZoneEngine, UniaxialStressUnderTopTractionRelaxesToTheExactState) {
  constexpr double kK = 21.443e9, kG = 16.083e9, kRho = 2420.0;
  const double w = 0.4, h = 0.3, q = 3e6;  // 3 MPa, as the direct-shear normal stress
  Model m;
  m.materials.push_back(std::make_unique<RockMaterialAdapter<ElasticRock>>(ElasticRock::Params{kRho, kK, kG}));
  // Unstructured mesh of a rectangle: the state is uniform whatever the zone shapes.
  add_deformable_block(m, mesh_polygon({{0, 0}, {w, 0}, {w, h}, {0, h}}, 0.05), 0, "block", 0);

  EngineSettings s;
  Engine e(m, s);
  e.add_condition(std::make_unique<FixedCondition>(select_face(m, 0, {0, -1}), false, true, false));
  e.add_condition(std::make_unique<FixedCondition>(select_face(m, 0, {-1, 0}), true, false, false));
  e.add_condition(std::make_unique<TractionCondition>(select_face(m, 0, {0, 1}), TimeFunction::constant(q),
                                                      TimeFunction::constant(0.0)));
  e.begin_stage("load", Damping{});
  // Converged when the largest unbalanced gridpoint force (GridPoint::f of the last step, free
  // components) is below 1e-9 of the load on one boundary edge.
  auto unbalanced = [&] {
    double f = 0.0;
    for (const auto& g : m.gp) {
      if (!g.fixed_x) f = std::max(f, std::abs(g.f.x()));
      if (!g.fixed_y) f = std::max(f, std::abs(g.f.y()));
    }
    return f / (q * 0.05);
  };
  long steps = 0;
  while (steps < 200000) {
    e.run_steps(100);
    steps += 100;
    if (unbalanced() < 1e-9) break;
  }
  const double en = 9 * kK * kG / (3 * kK + kG), nu = (3 * kK - 2 * kG) / (2 * (3 * kK + kG));
  const double settlement = q * h * (1 - nu * nu) / en;
  double top = 0.0;
  int ntop = 0;
  for (const auto& g : m.gp)
    if (std::abs(g.x0.y() - h) < 1e-12) {
      top += g.x.y() - g.x0.y();
      ++ntop;
    }
  top /= ntop;
  std::cout << "[          ] " << steps << " steps, unbalanced force / edge load " << unbalanced() << ", settlement "
            << -top << " m (exact " << settlement << ")\n";
  for (const Zone& z : m.zones) {
    EXPECT_NEAR(z.stress[1], -q, 1e-4 * q);
    EXPECT_NEAR(z.stress[0], 0.0, 1e-4 * q);
    EXPECT_NEAR(z.stress[2], 0.0, 1e-4 * q);
    EXPECT_NEAR(z.szz, -nu * q, 1e-4 * q);
  }
  EXPECT_NEAR(-top, settlement, 1e-4 * settlement);
}
