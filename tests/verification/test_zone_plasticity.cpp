// Plane-strain compression of a Mohr-Coulomb block through the engine: smooth platens (rollers at
// the base, prescribed downward velocity on the top face), the left side on rollers and a constant
// confining traction q on the right side. The state stays homogeneous, so every zone must reach
// the Mohr-Coulomb limit sigma_yy = -q N_phi - 2 c sqrt(N_phi) (Itasca FLAC Constitutive Models,
// Mohr-Coulomb model; Jaeger, Cook & Zimmerman, Fundamentals of Rock Mechanics, sec. 4.5), with
// sigma_xx = -q, and hold it as a flat plateau while the top keeps moving.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#include "framework/boundary/conditions.hpp"
#include "framework/boundary/fixed_condition.hpp"
#include "framework/boundary/traction_condition.hpp"
#include "framework/boundary/velocity_condition.hpp"
#include "framework/mechanics/engine.hpp"
#include "framework/mechanics/zones.hpp"
#include "models/rock/mohr_coulomb_rock.hpp"

using namespace rockdem;

TEST(ZonePlasticity, BiaxialCompressionPlateauIsTheMohrCoulombStrength) {
  const double w = 0.1, h = 0.2, q = 5e6, v = 0.05;  // confinement 5 MPa, top velocity 50 mm/s
  const MohrCoulombRock::Params p{2500.0, 20e9, 12e9, 30.0 * M_PI / 180, 2e6, 0.0, 1e6};
  Model m;
  m.materials.push_back(std::make_unique<RockMaterialAdapter<MohrCoulombRock>>(p));
  add_deformable_block(m, mesh_polygon({{0, 0}, {w, 0}, {w, h}, {0, h}}, 0.025), 0, "sample", 0);

  Engine e(m, EngineSettings{});
  e.add_condition(std::make_unique<FixedCondition>(select_face(m, 0, {0, -1}), false, true, false));
  e.add_condition(std::make_unique<FixedCondition>(select_face(m, 0, {-1, 0}), true, false, false));
  e.add_condition(std::make_unique<TractionCondition>(select_face(m, 0, {1, 0}), TimeFunction::constant(q),
                                                      TimeFunction::constant(0.0)));
  e.add_condition(std::make_unique<VelocityCondition>(select_face(m, 0, {0, 1}), false, std::nullopt,
                                                      TimeFunction::constant(-v), std::nullopt));
  e.begin_stage("compress", Damping{});

  const double nphi = (1 + std::sin(p.friction)) / (1 - std::sin(p.friction));
  const double limit = -q * nphi - 2 * p.cohesion * std::sqrt(nphi);  // -21.93 MPa
  // Axial strain to the limit is about |limit - (-q)| / E' ~ 5e-4; run to 3e-3.
  const double strain_end = 3e-3;
  auto mean_syy = [&] {
    double s = 0.0, a = 0.0;
    for (const Zone& z : m.zones) {
      s += z.stress[1] * z.area;
      a += z.area;
    }
    return s / a;
  };
  std::vector<double> plateau;
  while (e.stage_time() * v / h < strain_end) {
    e.run_steps(200);
    const double strain = e.stage_time() * v / h;
    if (strain > 1.5e-3) plateau.push_back(mean_syy());
  }
  ASSERT_GT(plateau.size(), 10u);
  const auto [lo, hi] = std::minmax_element(plateau.begin(), plateau.end());
  std::cout << "[          ] " << m.step << " steps; plateau sigma_yy " << *lo / 1e6 << " .. " << *hi / 1e6
            << " MPa, Mohr-Coulomb limit " << limit / 1e6 << " MPa\n";
  // The loading rate adds an overshoot (measured 0.08-0.15 %); 0.5 % of the strength bounds it.
  EXPECT_NEAR(*lo, limit, 5e-3 * std::abs(limit));
  EXPECT_NEAR(*hi, limit, 5e-3 * std::abs(limit));
  for (const Zone& z : m.zones) {
    MohrCoulombRock::State st;
    std::memcpy(&st, z.material_state.data(), sizeof st);
    EXPECT_GT(st.plastic_shear, 0.0);
    // Zone by zone, the plastic flow on this irregular mesh scatters the stresses by about 1 %,
    // and the scatter follows the last bits of the computation: the zone furthest from the
    // confinement was 0.96 % off it with the stress rotation through atan/sin/cos, 1.15 % with
    // the same rotation in rational form, 1.61 % with the rotation angle raised by one part in
    // 2e15 (the plateau above stayed within 0.01 % of itself each time). The physics is the
    // plateau; each zone is held to 2.5 %.
    EXPECT_NEAR(z.stress[0], -q, 0.025 * q);
    EXPECT_NEAR(z.stress[1], limit, 0.025 * std::abs(limit));
  }
}
