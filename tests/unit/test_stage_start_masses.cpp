// A stage whose mass scaling raises the masses keeps each moving point's momentum at its start,
// whatever its damping (Engine::compute_time_step). A quasi-static rest after an earthquake
// scales the masses up a hundredfold; holding the event's last velocities under them carried a
// hundred times the model's kinetic energy into the rest, which the relaxation spent in joint
// slip. A checkpoint carries the masses the rule compares with, so a run restarted at the stage
// boundary begins the next stage as the uninterrupted run does.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "framework/mechanics/engine.hpp"
#include "tests/unit/vibrating_square.hpp"

using namespace rockdem;

namespace {

Damping local() {
  Damping d;
  d.kind = Damping::Kind::local;
  return d;
}

// The "earthquake" with real masses for 50 steps; then the engine is set to scale its masses to a
// step 20 times longer, as a rest would.
double shake(Engine& e) {
  e.begin_stage("event", Damping{});
  for (int i = 0; i < 50; ++i) e.step();
  const double dt = e.dt();
  e.set_mass_scaling_dt(20.0 * dt);
  return dt;
}

std::vector<Vec2> velocities(const Model& m) {
  std::vector<Vec2> v;
  for (const GridPoint& g : m.gp) v.push_back(g.v);
  return v;
}

}  // namespace

TEST(StageStartMasses, RaisedMassesKeepEachPointsMomentum) {
  Model m;
  test::build_vibrating_square(m);
  Engine e(m, EngineSettings{});
  const double dt = shake(e);
  const std::vector<Vec2> v0 = velocities(m);
  e.begin_stage("rest", local());
  ASSERT_GT(e.dt(), 10.0 * dt);
  // Each gridpoint's new mass, m = k (D / (2 dt_safety))^2 for the step D (at least its own).
  const double target = 20.0 * dt / (2.0 * EngineSettings{}.dt_safety);
  double k_before = 0.0, k_after = 0.0, k_held = 0.0;
  for (std::size_t i = 0; i < m.gp.size(); ++i) {
    const GridPoint& g = m.gp[i];
    const double scaled = std::max(g.mass, g.stiffness * target * target);
    ASSERT_GT(scaled, 50.0 * g.mass) << i;
    EXPECT_NEAR(g.v.x(), v0[i].x() * g.mass / scaled, 1e-12 * std::abs(v0[i].x())) << i;
    EXPECT_NEAR(g.v.y(), v0[i].y() * g.mass / scaled, 1e-12 * std::abs(v0[i].y())) << i;
    k_before += 0.5 * g.mass * v0[i].squaredNorm();
    k_after += 0.5 * scaled * g.v.squaredNorm();
    k_held += 0.5 * scaled * v0[i].squaredNorm();
  }
  // The kinetic energy the scaled masses carry falls by the mass ratio; held velocities would
  // have raised it by that ratio.
  EXPECT_LT(k_after, 0.02 * k_before);
  EXPECT_GT(k_held, 50.0 * k_before);
}

TEST(StageStartMasses, RestartAtTheStageBoundaryBeginsTheStageAlike) {
  Model a, b, c;
  test::build_vibrating_square(a);
  test::build_vibrating_square(b);
  test::build_vibrating_square(c);
  Engine ea(a, EngineSettings{});
  shake(ea);
  const std::map<std::string, std::vector<double>> saved = ea.saved_state();
  ASSERT_TRUE(saved.count("engine.inertial_mass"));
  // The restarted runs: the model state as the checkpoint has it, the engine's from its arrays
  // (b) or, as from a checkpoint written before the masses were kept, without them (c).
  ModelSnapshot snap;
  snap.take(a);
  ASSERT_TRUE(snap.put(b));
  ASSERT_TRUE(snap.put(c));
  Engine eb(b, EngineSettings{}), ec(c, EngineSettings{});
  eb.restore_state(saved, "checkpoint.h5");
  std::map<std::string, std::vector<double>> old = saved;
  old.erase("engine.inertial_mass");
  old.erase("engine.block_masses");
  ec.restore_state(old, "old_checkpoint.h5");
  for (Engine* e : {&eb, &ec}) e->set_mass_scaling_dt(ea.settings().mass_scaling_dt);
  ea.begin_stage("rest", local());
  eb.begin_stage("rest", local());
  ec.begin_stage("rest", local());
  bool differs = false;
  for (std::size_t i = 0; i < a.gp.size(); ++i) {
    EXPECT_EQ(a.gp[i].v, b.gp[i].v) << i;
    differs = differs || a.gp[i].v != c.gp[i].v;
  }
  EXPECT_TRUE(differs) << "without the masses the stage starts with the held velocities";
  for (int i = 0; i < 20; ++i) {
    ea.step();
    eb.step();
  }
  for (std::size_t i = 0; i < a.gp.size(); ++i) EXPECT_EQ(a.gp[i].x, b.gp[i].x) << i;
}
