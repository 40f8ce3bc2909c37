// How one contact-detection pass and one step grow with the size of a jointed rock mass (a plain
// timed executable, not a test; no thresholds):
//
//   rockdem_bench_rock_mass [--blocks N] [--deformable 0|1] [--cells C] [--passes N] [--steps N] [--threads T]
//
// The rock mass: a rectangle cut by two orthogonal joint sets at 1 m spacing into about N square
// blocks (side ceil(sqrt(N)) blocks), the vertical joints of every other row shifted by half a
// spacing (a brick pattern, so that no four corners meet at one point), on a fixed rigid base,
// gravity, coulomb_slip joints (kn = 10 GPa/m, ks = 5 GPa/m, 30 deg), rounding 1 mm, detection
// tolerance 1 mm. Blocks are rigid, or deformable (elastic tuff, each block C x C cells of two
// triangles, default C = 4: 16 boundary gridpoints a block).
//
// Timed, after one detection and the stable step outside the clock: `passes` calls of
// detect_contacts (one detection pass: broad phase, narrow phase, merge, contact lengths), then
// `steps` engine steps (local damping; a detection every 10 steps, the engine default). Prints
// per pass and per step, in microseconds per block, and a RESULT line. --threads T: the engine's
// loops on T threads (EngineSettings::threads); CPU figures are then all threads' together.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <map>
#include <string>
#include <vector>

#include "framework/boundary/fixed_condition.hpp"
#include "framework/geometry/mesh.hpp"
#include "framework/mechanics/engine.hpp"
#include "framework/mechanics/zones.hpp"
#include "framework/plugin_api/joint_law.hpp"
#include "framework/plugin_api/rock_material.hpp"

namespace {

using namespace rockdem;
using Clock = std::chrono::steady_clock;

RawValue raw(const std::string& v) { return RawValue{v, "bench"}; }

double arg(const std::map<std::string, std::string>& kv, const std::string& k, double def) {
  auto it = kv.find(k);
  return it == kv.end() ? def : std::stod(it->second);
}

// Returns the base block's index.
int build(Model& m, int side, bool deformable, int cells) {
  m.gravity = Vec2(0.0, -9.81);
  m.contacts.rounding = 1e-3;
  m.contacts.models.push_back(make_joint_model(
      "coulomb_slip", RawValues{{"kn", raw("10 GPa/m")}, {"ks", raw("5 GPa/m")}, {"friction", raw("30 deg")}}, {}, "bench"));
  m.contacts.model_names.push_back("joint");
  m.contacts.assignments.push_back({-1, -1, 0});
  if (deformable)
    m.materials.push_back(RockMaterialRegistry::instance().get("elastic", "rock material", "bench").make(
        RawValues{{"density", raw("2418.8 kg/m3")}, {"bulk", raw("20.96 GPa")}, {"shear", raw("14.41 GPa")}}, "bench"));
  const double s = 1.0;
  int id = 0;
  for (int row = 0; row < side; ++row) {
    const double shift = (row % 2) * 0.5 * s;
    for (int col = 0; col < side; ++col) {
      const double x0 = col * s + shift, y0 = row * s;
      const std::string name = "b" + std::to_string(id++);
      if (deformable)
        add_deformable_block(m, mesh_rectangle(x0, y0, s, s, cells, cells), 0, name, 0);
      else
        add_rigid_block(m, Polygon{Vec2(x0, y0), Vec2(x0 + s, y0), Vec2(x0 + s, y0 + s), Vec2(x0, y0 + s)}, 2418.8, name, 0);
    }
  }
  return add_rigid_block(m, Polygon{Vec2(-1, -1), Vec2(side + 1.5, -1), Vec2(side + 1.5, 0), Vec2(-1, 0)}, 2418.8, "base", 0);
}

double cpu_now() { return static_cast<double>(std::clock()) / CLOCKS_PER_SEC; }

}  // namespace

int main(int argc, char** argv) {
  std::map<std::string, std::string> kv;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string k = argv[i];
    if (k.rfind("--", 0) != 0) {
      std::fprintf(stderr, "usage: %s [--blocks N] [--deformable 0|1] [--cells C] [--passes N] [--steps N] [--threads T]\n", argv[0]);
      return 2;
    }
    kv[k.substr(2)] = argv[i + 1];
  }
  const int side = static_cast<int>(std::ceil(std::sqrt(arg(kv, "blocks", 1024))));
  const bool deformable = arg(kv, "deformable", 0) != 0.0;
  const int cells = static_cast<int>(arg(kv, "cells", 4));
  const int passes = static_cast<int>(arg(kv, "passes", 20));
  const long steps = static_cast<long>(arg(kv, "steps", 100));
  try {
    Model m;
    const int base = build(m, side, deformable, cells);
    EngineSettings s;
    s.detection.distance = 2e-3;
    s.threads = static_cast<int>(arg(kv, "threads", 1));
    Engine e(m, s);
    FaceSelection sel;
    sel.block = base;
    sel.points = m.blocks[base].boundary;
    e.add_condition(std::make_unique<FixedCondition>(sel, true, true, true));
    e.begin_stage("bench", Damping{});
    const std::size_t nb = m.blocks.size() - 1;
    auto t0 = Clock::now();
    double c0 = cpu_now();
    for (int i = 0; i < passes; ++i) detect_contacts(m, s.detection, s.threads);
    const double detect_wall = std::chrono::duration<double>(Clock::now() - t0).count() / passes;
    const double detect_cpu = (cpu_now() - c0) / passes;
    const std::size_t contacts = m.contacts.items.size();
    // The parts of a pass: the contact lengths alone (update_contact_lengths, part of every pass).
    t0 = Clock::now();
    c0 = cpu_now();
    for (int i = 0; i < passes; ++i) update_contact_lengths(m, s.detection, s.threads);
    const double lengths_cpu = (cpu_now() - c0) / passes;
    t0 = Clock::now();
    c0 = cpu_now();
    e.run_steps(steps);
    const double step_wall = std::chrono::duration<double>(Clock::now() - t0).count() / static_cast<double>(steps);
    const double step_cpu = (cpu_now() - c0) / static_cast<double>(steps);
    std::printf("%s rock mass: %zu blocks (%d x %d, brick pattern), %zu gridpoints, %zu zones, %zu contacts\n",
                deformable ? "deformable" : "rigid", nb, side, side, m.gp.size(), m.zones.size(), contacts);
    std::printf("detection pass: %.3f ms wall, %.3f ms CPU = %.3f us CPU per block\n", detect_wall * 1e3, detect_cpu * 1e3,
                detect_cpu * 1e6 / static_cast<double>(nb));
    std::printf("  of which contact lengths: %.3f ms CPU = %.3f us CPU per block\n", lengths_cpu * 1e3,
                lengths_cpu * 1e6 / static_cast<double>(nb));
    std::printf("step: %.3f ms wall, %.3f ms CPU = %.3f us CPU per block\n", step_wall * 1e3, step_cpu * 1e3,
                step_cpu * 1e6 / static_cast<double>(nb));
    std::printf("RESULT kind=rock_mass deformable=%d blocks=%zu contacts=%zu detect_cpu_us_per_block=%.4f "
                "lengths_cpu_us_per_block=%.4f step_cpu_us_per_block=%.4f detect_wall_s=%.6f step_wall_s=%.6f\n",
                deformable ? 1 : 0, nb, contacts, detect_cpu * 1e6 / static_cast<double>(nb),
                lengths_cpu * 1e6 / static_cast<double>(nb),
                step_cpu * 1e6 / static_cast<double>(nb), detect_wall, step_wall);
  } catch (const std::exception& ex) {
    std::fprintf(stderr, "error: %s\n", ex.what());
    return 1;
  }
  return 0;
}
