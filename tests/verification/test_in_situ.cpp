// Verification test 3 of issue 10: a rock mass of rigid blocks started from its in-situ stress
// (sigma_v = rho g z, sigma_H = 0.5 sigma_v) is in equilibrium at once. The model rests on rollers
// (sides: vx = 0, base: vy = 0, selected by region); the contacts are pre-loaded with the traction
// the field puts on them. Checked: the unbalanced-force ratio of the first step (< 1e-3), and
// after 10,000 steps of local damping every contact's normal and shear stress against the field
// at its point (0.1 % of the largest in-situ stress) and every block's displacement (< 1e-6 m).
// Two layouts: a regular grid (every junction a four-corner point: the statement) and a
// brick wall (joints staggered by half a block; T-junctions). Measured: first-step ratio ~1e-16,
// stress error ~2e-16 of sigma_v(base), no block moved. Before the contacts between shared corners
// were rewritten, side-by-side blocks got 2 mm diagonal corner contacts instead of edge contacts
// on their vertical joints (first-step ratio 0.78 for the grid, 0.017 for the bricks).
// Also: two deformable layers, see DeformableLayersStartInEquilibrium below.
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>
#include <string>

#include "framework/io/case.hpp"
#include "framework/mechanics/engine.hpp"
#include "framework/mechanics/in_situ.hpp"

using namespace rockdem;

namespace {

constexpr double kRho = 2650.0, kG = 9.81, kK = 0.5;
constexpr int kCols = 5, kRows = 5;  // 1 m blocks: a 5 m x 5 m mass

std::string mass_case(bool bricks) {
  std::ostringstream os;
  os.precision(12);
  os << "title = \"in-situ rock mass\"\n[model]\nrounding = \"1 mm\"\ndetection_tolerance = \"1 mm\"\n"
     << "gravity = [\"0 m/s2\", \"" << -kG << " m/s2\"]\n"
     << "[[joints]]\nname = \"j\"\nlaw = \"coulomb_slip\"\nbetween = [\"rock\", \"rock\"]\n"
     << "kn = \"10 GPa/m\"\nks = \"5 GPa/m\"\nfriction = \"35 deg\"\n";
  int id = 0;
  for (int r = 0; r < kRows; ++r) {
    // Brick rows alternate: whole blocks, or half blocks at both ends.
    std::vector<std::pair<double, double>> cells;  // x0, width
    if (bricks && r % 2 == 1) {
      cells.push_back({0.0, 0.5});
      for (int i = 0; i < kCols - 1; ++i) cells.push_back({0.5 + i, 1.0});
      cells.push_back({kCols - 0.5, 0.5});
    } else {
      for (int i = 0; i < kCols; ++i) cells.push_back({double(i), 1.0});
    }
    for (const auto& [x0, w] : cells)
      os << "[[blocks]]\nname = \"b" << id++ << "\"\ngroup = \"rock\"\ntype = \"rigid\"\ndensity = \"" << kRho
         << " kg/m3\"\nrectangle = [\"" << x0 << " m\", \"" << r << " m\", \"" << w << " m\", \"1 m\"]\n";
  }
  os << "[in_situ]\nsurface = \"" << kRows << " m\"\nK = " << kK << "\n"
     << "[[boundary]]\ntype = \"fixed\"\ncomponents = [\"x\"]\nline = {from = [\"0 m\", \"0 m\"], to = [\"0 m\", \"" << kRows
     << " m\"], tolerance = \"1 mm\"}\n"
     << "[[boundary]]\ntype = \"fixed\"\ncomponents = [\"x\"]\nline = {from = [\"" << kCols << " m\", \"0 m\"], to = [\""
     << kCols << " m\", \"" << kRows << " m\"], tolerance = \"1 mm\"}\n"
     << "[[boundary]]\ntype = \"fixed\"\ncomponents = [\"y\"]\nbox = [\"-1 m\", \"-1 mm\", \"" << kCols + 1
     << " m\", \"1 mm\"]\n"
     << "[[stages]]\nname = \"equilibrium\"\nuntil = \"steps\"\nsteps = 10000\n";
  return os.str();
}

struct Outcome {
  double first_ratio = 0.0, stress_error = 0.0, largest_move = 0.0;
  std::size_t contacts = 0;
};

Outcome run_mass(bool bricks) {
  Case c = load_case_text(mass_case(bricks), bricks ? "bricks.toml" : "grid.toml", ".");
  Engine e(c.model, c.settings);
  for (auto& bc : c.conditions) e.add_condition(std::move(bc));
  const Model& m = c.model;
  initialise_in_situ(c.model, *c.in_situ, c.settings.detection);
  e.begin_stage("equilibrium", c.stages[0].damping);
  Outcome o;
  e.step();
  o.first_ratio = e.unbalanced_ratio();
  e.run_steps(9999);
  const double scale = kRho * kG * kRows;  // the largest in-situ stress (sigma_v at the base)
  for (const Contact& ct : m.contacts.items) {
    if (ct.response.open) continue;
    const Vec2 n = ct.normal, t(n.y(), -n.x());
    const Vec2 tr = c.in_situ->traction(m.gp[ct.point].x, n);
    o.stress_error = std::max(o.stress_error, std::abs(ct.response.sigma_n + n.dot(tr)) / scale);
    o.stress_error = std::max(o.stress_error, std::abs(ct.response.tau - t.dot(tr)) / scale);
    ++o.contacts;
  }
  for (const Block& b : m.blocks) o.largest_move = std::max(o.largest_move, (b.xc - b.xc0).norm());
  return o;
}

void expect_equilibrium(const Outcome& o, const char* layout) {
  std::cout << layout << ": first-step ratio " << o.first_ratio << ", stress error " << o.stress_error
            << " of sigma_v(base), largest block move " << o.largest_move << " m over " << o.contacts << " contacts\n";
  EXPECT_LT(o.first_ratio, 1e-3);
  EXPECT_LT(o.stress_error, 1e-3);
  EXPECT_LT(o.largest_move, 1e-6);
}

}  // namespace

TEST(InSitu, BrickWallOfRigidBlocksStartsInEquilibrium) { expect_equilibrium(run_mass(true), "bricks"); }

// The statement: every junction a four-corner point.
TEST(InSitu, RegularGridOfRigidBlocksStartsInEquilibrium) { expect_equilibrium(run_mass(false), "grid"); }

// Two deformable layers of an elastic rock on rollers (base), loaded on their sides and on the
// exposed strips of the lower layer's top by the field itself (boundary kind in_situ, selected by
// region): zones start from the field at their centroids, the contacts of the horizontal joint
// from its traction. sigma_v = rho g z below the top of the upper layer, sigma_H = 0.5 sigma_v.
namespace {

std::string layers_case() {
  std::ostringstream os;
  os.precision(12);
  os << "title = \"in-situ deformable layers\"\n[model]\nrounding = \"1 mm\"\ndetection_tolerance = \"1 mm\"\n"
     << "gravity = [\"0 m/s2\", \"" << -kG << " m/s2\"]\n"
     << "[[materials]]\nname = \"tuff\"\nmodel = \"elastic\"\ndensity = \"" << kRho << " kg/m3\"\nbulk = \"10 GPa\"\nshear = \"6 GPa\"\n"
     << "[[joints]]\nname = \"j\"\nlaw = \"coulomb_slip\"\nbetween = [\"rock\", \"rock\"]\n"
     << "kn = \"10 GPa/m\"\nks = \"5 GPa/m\"\nfriction = \"35 deg\"\n"
     << "[[blocks]]\nname = \"lower\"\ngroup = \"rock\"\ntype = \"deformable\"\nmaterial = \"tuff\"\n"
     << "rectangle = [\"0 m\", \"0 m\", \"5 m\", \"2.5 m\"]\nzones = [20, 10]\n"
     << "[[blocks]]\nname = \"upper\"\ngroup = \"rock\"\ntype = \"deformable\"\nmaterial = \"tuff\"\n"
     << "rectangle = [\"0.25 m\", \"2.5 m\", \"4.5 m\", \"2.5 m\"]\nzones = [18, 10]\n"
     << "[in_situ]\nsurface = \"5 m\"\nK = " << kK << "\n"
     << "[[boundary]]\ntype = \"fixed\"\ncomponents = [\"y\"]\nbox = [\"-1 m\", \"-1 mm\", \"6 m\", \"1 mm\"]\n";
  // Sides of both layers and the strips of the lower layer's top that the upper one leaves bare.
  for (const char* box : {"[\"-1 mm\", \"-1 mm\", \"1 mm\", \"2.5 m\"]", "[\"4.999 m\", \"-1 mm\", \"5.001 m\", \"2.5 m\"]",
                          "[\"0.249 m\", \"2.5 m\", \"0.251 m\", \"5 m\"]", "[\"4.749 m\", \"2.5 m\", \"4.751 m\", \"5 m\"]",
                          "[\"-1 mm\", \"2.499 m\", \"0.251 m\", \"2.501 m\"]", "[\"4.749 m\", \"2.499 m\", \"5.001 m\", \"2.501 m\"]"})
    os << "[[boundary]]\ntype = \"in_situ\"\nbox = " << box << "\n";
  os << "[[stages]]\nname = \"equilibrium\"\nuntil = \"steps\"\nsteps = 10000\n";
  return os.str();
}

}  // namespace

TEST(InSitu, DeformableLayersStartInEquilibrium) {
  Case c = load_case_text(layers_case(), "layers.toml", ".");
  Engine e(c.model, c.settings);
  for (auto& bc : c.conditions) e.add_condition(std::move(bc));
  const Model& m = c.model;
  const InSituReport rep = initialise_in_situ(c.model, *c.in_situ, c.settings.detection);
  e.begin_stage("equilibrium", c.stages[0].damping);
  e.step();
  const double first_ratio = e.unbalanced_ratio();
  e.run_steps(9999);
  const double scale = kRho * kG * 5.0;  // sigma_v at the base
  double zone_error = 0.0, contact_error = 0.0, move = 0.0;
  for (const Zone& z : m.zones) {
    const Vec2 xc = (m.gp[z.n[0]].x0 + m.gp[z.n[1]].x0 + m.gp[z.n[2]].x0) / 3.0;
    zone_error = std::max(zone_error, (z.stress - c.in_situ->at(xc)).cwiseAbs().maxCoeff() / scale);
  }
  std::size_t closed = 0;
  for (const Contact& ct : m.contacts.items) {
    if (ct.response.open) continue;
    const Vec2 n = ct.normal, t(n.y(), -n.x());
    const Vec2 tr = c.in_situ->traction(m.gp[ct.point].x, n);
    contact_error = std::max(contact_error, std::abs(ct.response.sigma_n + n.dot(tr)) / scale);
    contact_error = std::max(contact_error, std::abs(ct.response.tau - t.dot(tr)) / scale);
    ++closed;
  }
  for (const GridPoint& g : m.gp) move = std::max(move, (g.x - g.x0).norm());
  std::cout << "layers: " << rep.zones << " zones, " << rep.contacts << " contacts pre-loaded; first-step ratio "
            << first_ratio << "; after 10,000 steps: zone stress error " << zone_error << ", contact stress error "
            << contact_error << " (of sigma_v at the base, " << closed << " closed contacts), largest move " << move
            << " m\n";
  EXPECT_GT(closed, 20u);
  EXPECT_LT(first_ratio, 1e-3);
  EXPECT_LT(zone_error, 1e-3);
  EXPECT_LT(contact_error, 1e-3);
  EXPECT_LT(move, 1e-6);
}
