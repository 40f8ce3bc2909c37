// The energy balance (framework/mechanics/energy_balance.hpp) through the whole engine, against
// what must hold exactly in undamped elastic dynamics and against closed forms:
// - a rigid block dropped flat onto a wider fixed block, undamped, elastic Coulomb joint with
//   high friction: it bounces back to its drop height without rotating, and the balance closes;
// - a block sliding on an incline (gravity tilted): the energy dissipated by slip is mu N slip;
// - a deformable elastic block vibrating freely: kinetic + strain energy stays constant;
// - boundaries doing work: a block compressed by a prescribed velocity and pushed by a traction;
// - a deformable block settling on a fixed base under local damping: the damping's dissipation
//   closes the balance.
// Verification test 4 of issue 10, energy part (docs/verification.md).
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <numbers>

#include "framework/boundary/fixed_condition.hpp"
#include "framework/boundary/traction_condition.hpp"
#include "framework/boundary/velocity_condition.hpp"
#include "framework/core/params.hpp"
#include "framework/geometry/mesh.hpp"
#include "framework/mechanics/engine.hpp"
#include "framework/mechanics/zones.hpp"
#include "framework/plugin_api/joint_law.hpp"
#include "models/rock/elastic.hpp"

using namespace rockdem;

namespace {

constexpr double kG = 9.81, kRho = 2500.0;

// A coulomb_slip joint between any two blocks: kn = ks = 10 GPa/m, friction in degrees.
void add_joint(Model& m, double friction_deg) {
  RawValues v;
  v["kn"] = RawValue{std::string("10 GPa/m"), "test"};
  v["ks"] = RawValue{std::string("10 GPa/m"), "test"};
  v["friction"] = RawValue{std::to_string(friction_deg) + " deg", "test"};
  m.contacts.models.push_back(make_joint_model("coulomb_slip", v, {}, "test"));
  m.contacts.model_names.push_back("joint");
  m.contacts.assignments.push_back({-1, -1, 0});
  m.contacts.rounding = 1e-3;
}

// The base: a fixed rigid block with its top face at y = 0.
int add_base(Model& m, double x0, double x1) {
  return add_rigid_block(m, Polygon{Vec2(x0, -0.5), Vec2(x1, -0.5), Vec2(x1, 0.0), Vec2(x0, 0.0)}, kRho, "base", 0);
}

void fix(Engine& e, const Model& m, int block) {
  FaceSelection sel;
  sel.block = block;
  sel.points = m.blocks[block].boundary;
  e.add_condition(std::make_unique<FixedCondition>(sel, true, true, true));
}

EngineSettings settings(double dt) {
  EngineSettings s;
  s.fixed_dt = dt;
  s.detection.distance = 2e-3;  // rounding 1 mm + tolerance 1 mm
  return s;
}

Damping none() {
  Damping d;
  d.kind = Damping::Kind::none;
  return d;
}

}  // namespace

// A 0.6 m x 0.5 m rigid block dropped from 10 mm onto a 2 m wide fixed block (so that no corners
// coincide), undamped. Contact lasts about pi sqrt(m/(kn w)) = 1.1 ms (110 steps of 10 us); the
// block must rise back to 10 mm within 0.5 %, its rotation stay below 1e-9 rad and the balance
// close within 1 % at every step.
TEST(Energy, RigidBlockBouncesBackToItsDropHeight) {
  const double h0 = 0.01;
  Model m;
  m.gravity = Vec2(0.0, -kG);
  add_joint(m, 45.0);
  const int base = add_base(m, -1.0, 1.0);
  const int blk = add_rigid_block(m, Polygon{Vec2(-0.3, h0), Vec2(0.3, h0), Vec2(0.3, h0 + 0.5), Vec2(-0.3, h0 + 0.5)},
                                  kRho, "block", 0);
  Engine e(m, settings(1e-5));
  fix(e, m, base);
  e.begin_stage("drop", none());
  e.energy();
  const double y0 = m.blocks[blk].xc.y();
  double worst = 0.0, rise = -1.0, theta = 0.0;
  bool bounced = false;
  for (int i = 0; i < 20000 && rise < 0.0; ++i) {
    const double vy_before = m.blocks[blk].vc.y();
    e.step();
    worst = std::max(worst, std::abs(e.energy().error));
    theta = std::max(theta, std::abs(m.blocks[blk].theta));
    if (vy_before < 0.0 && m.blocks[blk].vc.y() >= 0.0) bounced = true;
    // The apex: the upward velocity turns downward after the bounce.
    if (bounced && vy_before > 0.0 && m.blocks[blk].vc.y() <= 0.0) rise = m.blocks[blk].xc.y() - (y0 - h0);
  }
  const EnergyTerms& t = e.energy();
  std::cout << "[          ] bounce: rebound height " << rise * 1e3 << " mm of " << h0 * 1e3 << " mm ("
            << (rise / h0 - 1.0) * 100 << " %), max |rotation| " << theta << " rad, max |balance error| "
            << worst * 100 << " %, gravity work " << t.gravity_work << " J/m, slip " << t.slip << " J/m\n";
  ASSERT_GT(rise, 0.0) << "the block never came back up";
  EXPECT_NEAR(rise, h0, 0.005 * h0);
  EXPECT_LT(theta, 1e-9);
  EXPECT_LT(worst, 0.01);
}

// A 1 m x 0.5 m rigid block on a fixed base, gravity tilted by psi = 30 degrees, friction
// phi = 20 degrees, undamped, after settling normally under local damping. Over 0.5 s the slip
// dissipation must equal tan(phi) m g cos(psi) x (x the slip) within 1 %, x follow
// g (sin psi - cos psi tan phi) t^2 / 2 within 1 %, and the balance close within 1 %.
TEST(Energy, FrictionOnAnInclineDissipatesMuNTimesSlip) {
  const double psi = 30.0 * std::numbers::pi / 180.0, phi = 20.0 * std::numbers::pi / 180.0;
  Model m;
  add_joint(m, 20.0);
  const int base = add_base(m, -1.0, 12.0);
  const int blk = add_rigid_block(m, Polygon{Vec2(0, 0), Vec2(1, 0), Vec2(1, 0.5), Vec2(0, 0.5)}, kRho, "block", 0);
  Engine e(m, settings(2e-5));
  fix(e, m, base);
  // Settle on the normal component of gravity alone, so that sliding starts from rest.
  m.gravity = Vec2(0.0, -kG * std::cos(psi));
  e.begin_stage("settle", Damping{});
  for (int i = 0; i < 200 && !(i > 10 && e.unbalanced_ratio() < 1e-9); ++i) e.run_steps(100);
  m.gravity = Vec2(kG * std::sin(psi), -kG * std::cos(psi));
  e.begin_stage("slide", none());
  e.energy();
  const double x0 = m.blocks[blk].xc.x(), t0 = m.time;
  double worst = 0.0;
  while (m.time - t0 < 0.5) {
    e.step();
    worst = std::max(worst, std::abs(e.energy().error));
  }
  const EnergyTerms& t = e.energy();
  const double slip = m.blocks[blk].xc.x() - x0, T = m.time - t0;
  const double mass = m.blocks[blk].mass;
  const double expected = std::tan(phi) * mass * kG * std::cos(psi) * slip;
  const double x_exact = kG * (std::sin(psi) - std::cos(psi) * std::tan(phi)) * T * T / 2.0;
  std::cout << "[          ] incline: slip " << slip << " m (closed form " << x_exact << "), slip dissipation " << t.slip
            << " J/m, mu N slip " << expected << " J/m (" << (t.slip / expected - 1.0) * 100
            << " %), max |balance error| " << worst * 100 << " %\n";
  EXPECT_NEAR(slip, x_exact, 0.01 * x_exact);
  EXPECT_NEAR(t.slip, expected, 0.01 * expected);
  EXPECT_LT(worst, 0.01);
}

// A free 1 m x 0.5 m elastic block (20 x 10 cells), no gravity, no contact, released from a
// stretching velocity field v_x = v0 (x - 0.5)/0.5, undamped: kinetic + strain energy must stay
// within 0.5 % of the initial kinetic energy over 20 periods of the fundamental mode.
TEST(Energy, FreeElasticBlockKeepsKineticPlusStrain) {
  Model m;
  m.materials.push_back(std::make_unique<RockMaterialAdapter<ElasticRock>>(ElasticRock::Params{kRho, 20e9, 15e9}));
  add_deformable_block(m, mesh_rectangle(0.0, 0.0, 1.0, 0.5, 20, 10), 0, "block", 0);
  const double v0 = 0.1;
  for (GridPoint& g : m.gp) g.v = Vec2(v0 * (g.x.x() - 0.5) / 0.5, 0.0);
  EngineSettings s;
  Engine e(m, s);
  e.begin_stage("free", none());
  e.energy();
  // Fundamental axial mode of a free bar: f = c / (2 L), c = sqrt((K + 4G/3) / rho) (plane strain).
  const double c = std::sqrt((20e9 + 4.0 * 15e9 / 3.0) / kRho), period = 2.0 * 1.0 / c;
  const long steps = static_cast<long>(20.0 * period / e.dt());
  double k0 = 0.0, worst = 0.0, worst_error = 0.0, strain_max = 0.0;
  for (long i = 0; i < steps; ++i) {
    e.step();
    const EnergyTerms& t = e.energy();
    if (i == 0) k0 = t.kinetic;
    worst = std::max(worst, std::abs(t.kinetic + t.strain - k0));
    worst_error = std::max(worst_error, std::abs(t.error));
    strain_max = std::max(strain_max, t.strain);
  }
  std::cout << "[          ] free block: " << steps << " steps (dt " << e.dt() << " s), initial kinetic " << k0
            << " J/m, largest strain energy " << strain_max << " J/m, max |K + U - K0| / K0 " << worst / k0 * 100
            << " %, max |balance error| " << worst_error * 100 << " %\n";
  EXPECT_GT(strain_max, 0.5 * k0);  // the energy really goes back and forth
  EXPECT_LT(worst, 0.005 * k0);
  EXPECT_LT(worst_error, 0.005);
}

// A 0.6 m x 0.3 m elastic block (12 x 6 cells) set 0.5 mm above a 2 m fixed rigid base, gravity,
// local damping, run until it rests: gravity's work must be accounted for by strain, contact
// and damping (kinetic energy is then nil) within 1 %, and damping must have taken most of it.
TEST(Energy, LocallyDampedSettleClosesTheBalance) {
  Model m;
  m.gravity = Vec2(0.0, -kG);
  add_joint(m, 30.0);
  m.materials.push_back(std::make_unique<RockMaterialAdapter<ElasticRock>>(ElasticRock::Params{kRho, 2e9, 1.5e9}));
  const int base = add_base(m, -1.0, 1.0);
  add_deformable_block(m, mesh_rectangle(-0.3, 5e-4, 0.6, 0.3, 12, 6), 0, "block", 0);
  EngineSettings s;
  s.detection.distance = 2e-3;
  Engine e(m, s);
  fix(e, m, base);
  e.begin_stage("settle", Damping{});
  e.energy();
  double worst = 0.0;
  long n = 0;
  for (; n < 400000; ++n) {
    e.step();
    worst = std::max(worst, std::abs(e.energy().error));
    if (n > 1000 && n % 100 == 0 && e.unbalanced_ratio() < 1e-7) break;
  }
  const EnergyTerms& t = e.energy();
  std::cout << "[          ] damped settle: " << n << " steps, gravity work " << t.gravity_work << " J/m, strain "
            << t.strain << ", contact " << t.contact << ", kinetic " << t.kinetic << ", damping " << t.damping
            << ", slip " << t.slip << " J/m; final balance error " << t.error * 100 << " %, max " << worst * 100 << " %\n";
  EXPECT_LT(e.unbalanced_ratio(), 1e-7);
  EXPECT_GT(t.damping, 0.5 * t.gravity_work);
  EXPECT_LT(std::abs(t.error), 0.01);
  EXPECT_LT(worst, 0.01);
}

// Boundaries doing work, undamped, no gravity: an elastic 0.5 m x 0.5 m block (10 x 10 cells) on
// a fixed base, its top face driven down at 1 mm/s; then the same block pushed by a 1 MPa
// traction on its left face (right face on rollers). Whatever the boundaries put in must be in
// the kinetic and strain energy: the balance within 1 % at every step, and the work of the
// traction equal to q times the area swept by the face (at the same whole step) within 1 %.
TEST(Energy, BoundaryWorkGoesIntoKineticAndStrainEnergy) {
  for (const bool traction : {false, true}) {
    Model m;
    m.materials.push_back(std::make_unique<RockMaterialAdapter<ElasticRock>>(ElasticRock::Params{kRho, 2e9, 1.5e9}));
    add_deformable_block(m, mesh_rectangle(0.0, 0.0, 0.5, 0.5, 10, 10), 0, "block", 0);
    Engine e(m, EngineSettings{});
    e.add_condition(std::make_unique<FixedCondition>(select_face(m, 0, {0, -1}), true, true, false));
    if (traction) {
      e.add_condition(std::make_unique<FixedCondition>(select_face(m, 0, {1, 0}), true, false, false));
      e.add_condition(std::make_unique<TractionCondition>(select_face(m, 0, {-1, 0}), TimeFunction::constant(1e6),
                                                          TimeFunction::constant(0.0)));
    } else {
      e.add_condition(std::make_unique<VelocityCondition>(select_face(m, 0, {0, 1}), false, std::nullopt,
                                                          TimeFunction::constant(-1e-3), std::nullopt));
    }
    e.begin_stage("load", none());
    e.energy();
    double worst = 0.0;
    for (int i = 0; i < 4000; ++i) {
      e.step();
      worst = std::max(worst, std::abs(e.energy().error));
    }
    const EnergyTerms& t = e.energy();
    // Area swept by the left face (its mean x displacement times its height): the traction's work.
    double swept = 0.0;
    if (traction) {
      const FaceSelection left = select_face(m, 0, {-1, 0});
      for (std::size_t k = 0; k < left.edges.size(); ++k) {
        const Block& B = m.blocks[0];
        const int n = static_cast<int>(B.boundary.size());
        const GridPoint& a = m.gp[B.boundary[left.edges[k]]];
        const GridPoint& b = m.gp[B.boundary[(left.edges[k] + 1) % n]];
        // At whole step n, where the balance stands: x(n) = x(n+1) - v(n+1/2) dt.
        const double ua = (a.x - a.v * e.dt() - a.x0).x(), ub = (b.x - b.v * e.dt() - b.x0).x();
        swept += 0.5 * (ua + ub) * std::abs(b.x0.y() - a.x0.y());
      }
    }
    std::cout << "[          ] " << (traction ? "traction" : "velocity") << ": boundary work " << t.boundary_work
              << " J/m, kinetic " << t.kinetic << ", strain " << t.strain << " J/m"
              << (traction ? ", q x swept area " + std::to_string(1e6 * swept) + " J/m" : std::string())
              << "; max |balance error| " << worst * 100 << " %\n";
    EXPECT_GT(t.boundary_work, 0.0);
    EXPECT_GT(t.strain, 0.1 * t.boundary_work);
    EXPECT_LT(worst, 0.01);
    if (traction) {
      EXPECT_NEAR(t.boundary_work, 1e6 * swept, 0.01 * t.boundary_work);
    }
  }
}
