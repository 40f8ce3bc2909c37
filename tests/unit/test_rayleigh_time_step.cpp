// Rayleigh damping's stiffness term and the stable time step; one-term Rayleigh damping.
// Central differences on a damped oscillator (c = beta k) are stable for
// w dt <= 2 (sqrt(1 + xi^2) - xi), xi = beta w / 2 (Belytschko, Liu & Moran 2000, sec. 6.3),
// i.e. dt <= sqrt(beta^2 + 4 m/k) - beta: the engine's step must obey it, or a model with
// stiffness-proportional damping blows up (a zone turned inside out within a few hundred steps
// of a rock-mass model before this was taken into account).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "framework/core/error.hpp"
#include "framework/mechanics/engine.hpp"
#include "tests/unit/vibrating_square.hpp"

using namespace rockdem;

namespace {

double kinetic(const Model& m) {
  double e = 0.0;
  for (const GridPoint& g : m.gp) e += 0.5 * g.mass * g.v.squaredNorm();
  return e;
}

}  // namespace

TEST(RayleighTimeStep, OneTermGivesTheFractionAtItsFrequency) {
  const double w = 2.0 * std::numbers::pi * 3.0;
  const Damping mass = Damping::rayleigh_mass(0.05, 3.0), stiff = Damping::rayleigh_stiffness(0.05, 3.0);
  EXPECT_EQ(mass.beta, 0.0);
  EXPECT_NEAR(mass.alpha / (2.0 * w), 0.05, 1e-15);
  EXPECT_EQ(stiff.alpha, 0.0);
  EXPECT_NEAR(stiff.beta * w / 2.0, 0.05, 1e-15);
}

TEST(RayleighTimeStep, StiffnessTermShortensTheStepByTheClosedForm) {
  for (double beta : {0.0, 1e-6, 1e-4}) {
    Model m;
    test::build_vibrating_square(m);
    EngineSettings s;
    Engine e(m, s);
    Damping d;
    d.kind = Damping::Kind::rayleigh;
    d.beta = beta;
    e.begin_stage("shake", d);
    double expected = 1e300;
    for (const GridPoint& g : m.gp) expected = std::min(expected, std::sqrt(beta * beta + 4.0 * g.mass / g.stiffness) - beta);
    EXPECT_NEAR(e.dt(), s.dt_safety * expected, 1e-12 * expected) << "beta " << beta;
    if (beta > 0.0) {
      // Far below the undamped step: the stiffness term dominates the smallest zones.
      double undamped = 1e300;
      for (const GridPoint& g : m.gp) undamped = std::min(undamped, 2.0 * std::sqrt(g.mass / g.stiffness));
      EXPECT_LT(e.dt(), s.dt_safety * undamped);
    }
    // Stable: the energy only falls (it grew without bound at the undamped step with beta = 1e-4).
    const double e0 = kinetic(m);
    e.run_steps(2000);
    EXPECT_TRUE(std::isfinite(kinetic(m)));
    if (beta > 0.0) {
      EXPECT_LT(kinetic(m), e0);
    }
  }
}

TEST(RayleighTimeStep, MassScalingReachesTheRequestedStepWithTheStiffnessTerm) {
  Model m;
  test::build_vibrating_square(m);
  EngineSettings s;
  s.mass_scaling_dt = 1e-4;
  Engine e(m, s);
  Damping d;
  d.kind = Damping::Kind::rayleigh;
  d.beta = 1e-3;
  e.begin_stage("shake", d);
  EXPECT_NEAR(e.dt(), 1e-4, 1e-15);  // the inverse of the closed form, to rounding
  EXPECT_GT(e.added_mass_fraction(), 0.0);
  const double e0 = kinetic(m);
  e.run_steps(500);
  EXPECT_TRUE(std::isfinite(kinetic(m)));
  EXPECT_LT(kinetic(m), e0);
}

TEST(RayleighTimeStep, CaseKeyRayleighTerms) {
  const std::string base = R"([[materials]]
name = "rock"
model = "elastic"
density = "2000 kg/m3"
bulk = "1 GPa"
shear = "0.5 GPa"
[[blocks]]
name = "b"
type = "deformable"
material = "rock"
rectangle = ["0 m", "0 m", "1 m", "1 m"]
zones = [1, 1]
[[stages]]
name = "s"
damping = "rayleigh"
damping_ratio = 0.05
)";
  const Case mass = load_case_text(base + "damping_frequency = \"2 Hz\"\nrayleigh_terms = \"mass\"\nduration = \"1 s\"\n", "c.toml", ".");
  EXPECT_DOUBLE_EQ(mass.stages[0].damping.alpha, Damping::rayleigh_mass(0.05, 2.0).alpha);
  EXPECT_EQ(mass.stages[0].damping.beta, 0.0);
  const Case stiff = load_case_text(base + "damping_frequency = \"2 Hz\"\nrayleigh_terms = \"stiffness\"\nduration = \"1 s\"\n", "c.toml", ".");
  EXPECT_EQ(stiff.stages[0].damping.alpha, 0.0);
  EXPECT_DOUBLE_EQ(stiff.stages[0].damping.beta, Damping::rayleigh_stiffness(0.05, 2.0).beta);
  auto error_of = [&](const std::string& extra) {
    try {
      load_case_text(base + extra + "duration = \"1 s\"\n", "c.toml", ".");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(error_of("damping_frequency = \"2 Hz\"\nrayleigh_terms = \"mas\"\n").find("did you mean 'mass'"), std::string::npos);
  EXPECT_NE(error_of("damping_frequency = [\"1 Hz\", \"5 Hz\"]\nrayleigh_terms = \"mass\"\n").find("give one"), std::string::npos);
}
