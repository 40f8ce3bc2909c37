// Engine throughput (a plain timed executable, not a test; no thresholds):
//
//   rockdem_bench_engine zones    [--cells N] [--steps N] [--reps N] [--threads T]
//       One deformable 1 m x 1 m tuff block (elastic, Table 4-1 test 9 moduli), fixed base,
//       gravity, meshed as N x N cells x 2 CST zones (N = 100: 20,000 zones), stepped with local
//       damping. Reports zone-steps per second per core.
//
//   rockdem_bench_engine contacts [--rows N] [--width W] [--steps N] [--reps N] [--seed S]
//                                 [--squeeze D] [--lammps DIR] [--chunk N] [--threads T]
//       A packed assembly of rigid convex hexagons under gravity on a fixed base: a dry-stone
//       wall of N courses (default 50 x 12 m, about 2,700 blocks) with random block lengths and
//       staggered open head joints (seeded, deterministic; see make_packing), each course sitting
//       D (default 20 um) deep in the one below, so every bed-joint contact is closed and loaded
//       from the first step. Reports contact-steps per second per core, contacts being the
//       touching contact points (block corner against a face) at the start of the timed run.
//       --lammps DIR writes the same packing as a LAMMPS data file (atom_style body
//       rounded/polygon) and an input script with the same stiffness, friction, time step and
//       step count (DIR/packing.data, DIR/in.packing); see scripts/bench/compare_lammps.sh.
//       --chunk N runs the steps as calls of Engine::run_steps(N), as `rockdem run` does with
//       N = 10 (each call checks the state); default: one call.
//
//   --threads T (both): the engine's loops on T threads (EngineSettings::threads; default 1).
//       The rates are then those of the process, not of one core; the CPU time is all threads'.
//
// Output: human-readable lines and one machine-readable line per repetition starting "RESULT"
// (wall seconds and process CPU seconds of the timed loop). Timing covers Engine::run_steps only (model building, first contact detection and the stable
// time step are outside the clock), measured with std::chrono::steady_clock; the process is
// single-threaded, so wall time is time on one core.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <memory>
#include <numbers>
#include <set>
#include <string>
#include <vector>

#include "framework/boundary/conditions.hpp"
#include "framework/boundary/fixed_condition.hpp"
#include "framework/geometry/mesh.hpp"
#include "framework/geometry/polygon.hpp"
#include "framework/mechanics/engine.hpp"
#include "framework/model/model.hpp"
#include "framework/mechanics/zones.hpp"
#include "framework/plugin_api/joint_law.hpp"
#include "framework/plugin_api/rock_material.hpp"

namespace {

using namespace rockdem;
using Clock = std::chrono::steady_clock;

RawValues vals(std::initializer_list<std::pair<std::string, std::string>> kv) {
  RawValues out;
  for (const auto& [k, v] : kv) out[k] = RawValue{v, "bench"};
  return out;
}

struct Args {
  std::map<std::string, std::string> kv;
  double num(const std::string& k, double def) const {
    auto it = kv.find(k);
    return it == kv.end() ? def : std::stod(it->second);
  }
  std::string str(const std::string& k, const std::string& def) const {
    auto it = kv.find(k);
    return it == kv.end() ? def : it->second;
  }
};

double median(std::vector<double> v) {
  if (v.empty()) return std::nan("");
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// ---------------------------------------------------------------------------------------------
// (a) zones

int bench_zones(const Args& a) {
  const int cells = static_cast<int>(a.num("cells", 100));
  const long steps = static_cast<long>(a.num("steps", 1000));
  const int reps = static_cast<int>(a.num("reps", 3));
  std::vector<double> rates, cpu_rates;
  for (int r = 0; r < reps; ++r) {
    Model m;
    m.gravity = Vec2(0.0, -9.81);
    m.materials.push_back(RockMaterialRegistry::instance().get("elastic", "rock material", "bench").make(
        vals({{"density", "2418.8 kg/m3"}, {"bulk", "20.96 GPa"}, {"shear", "14.41 GPa"}}), "bench"));
    const TriMesh mesh = mesh_rectangle(0.0, 0.0, 1.0, 1.0, cells, cells);
    const int b = add_deformable_block(m, mesh, 0, "block", 0);
    m.contacts.models.push_back(make_joint_model("coulomb_slip", vals({{"kn", "10 GPa/m"}, {"ks", "5 GPa/m"}, {"friction", "30 deg"}}), {}, "bench"));
    m.contacts.model_names.push_back("joint");
    m.contacts.assignments.push_back({-1, -1, 0});
    EngineSettings s;
    s.threads = static_cast<int>(a.num("threads", 1));
    Engine e(m, s);
    e.add_condition(std::make_unique<FixedCondition>(select_face(m, b, Vec2(0.0, -1.0)), true, true, false));
    e.begin_stage("bench", Damping{});
    const auto t0 = Clock::now();
    const std::clock_t cpu0 = std::clock();
    e.run_steps(steps);
    const double cpu = static_cast<double>(std::clock() - cpu0) / CLOCKS_PER_SEC;
    const double sec = std::chrono::duration<double>(Clock::now() - t0).count();
    const double zs = static_cast<double>(m.zones.size()) * static_cast<double>(steps) / sec;
    rates.push_back(zs);
    cpu_rates.push_back(static_cast<double>(m.zones.size()) * static_cast<double>(steps) / cpu);
    std::printf("zones rep %d: %zu zones, %zu gridpoints, %ld steps, dt %.3e s, %.3f s -> %.3e zone-steps/s, %.1f ns per zone-step\n",
                r + 1, m.zones.size(), m.gp.size(), steps, e.dt(), sec, zs, 1e9 / zs);
    std::printf("RESULT kind=zones rep=%d zones=%zu gridpoints=%zu steps=%ld seconds=%.6f cpu_seconds=%.6f zone_steps_per_s=%.6e\n", r + 1,
                m.zones.size(), m.gp.size(), steps, sec, cpu, zs);
  }
  std::printf("zones median: %.3e zone-steps/s per core (wall time), %.3e (process CPU time)\n", median(rates), median(cpu_rates));
  return 0;
}

// ---------------------------------------------------------------------------------------------
// (b) contacts: the packing

struct Packing {
  std::vector<Polygon> cells;   // counter-clockwise, absolute coordinates
  double x0 = 0, x1 = 0;        // extent of the courses
  double y0 = 0;                // top of the base (a fixed wall)
  double height = 0;            // course height
  double top = 0;               // top of the last course
};

// SplitMix64: a fixed, portable generator (std:: distributions differ between libraries).
struct Rng {
  std::uint64_t s;
  double next() {
    std::uint64_t x = (s += 0x9E3779B97F4A7C15ull);
    x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
    x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
    x ^= x >> 31;
    return static_cast<double>(x >> 11) * (1.0 / 9007199254740992.0);  // [0, 1)
  }
  double uniform(double a, double b) { return a + (b - a) * next(); }
};

// A dry-stone wall: `rows` courses of blocks of height h and random length (0.15 to 0.25 m),
// with open head joints (gap 5 mm, beyond every detection distance) staggered at random but at
// least 40 mm from the head joints of the course below, each block's top corners chamfered by
// 10 mm (so every block is a convex hexagon). Each course sits `squeeze` deep in the one below
// (and the first in the base), so every bed-joint contact is closed and loaded from the start.
// Contacts are then block corner against the face of the block above/below: two contact points
// per touching pair in both codes, and no coincident corners (which the 2021 LAMMPS
// body/rounded/polygon cannot take: more than 4 vertex-edge contacts per pair overflow a
// fixed-size array, "stack smashing detected"). Deterministic for a given seed.
Packing make_packing(int rows, double width, std::uint64_t seed, double squeeze) {
  Packing pk;
  const double h = 0.1, gap = 5e-3, chamfer = 0.01, min_offset = 0.04, min_len = 0.1;
  pk.height = h;
  pk.x0 = 0.0;
  pk.x1 = width;
  pk.y0 = 0.0;
  Rng rng{seed};
  std::vector<double> below;  // head-joint centres of the course below
  double y = pk.y0 - squeeze;
  for (int r = 0; r < rows; ++r) {
    std::vector<double> joints;
    double x = pk.x0 + rng.uniform(0.0, 0.2);  // first block starts here (a ragged wall end)
    if (x - pk.x0 < min_len) x = pk.x0;        // (no sliver at the start: begin at x0)
    std::vector<std::pair<double, double>> spans;
    if (x > pk.x0) spans.push_back({pk.x0, x - gap}), joints.push_back(x - 0.5 * gap);
    while (true) {
      double end = x + rng.uniform(0.15, 0.25);
      for (int it = 0; it < 20; ++it) {  // keep this joint away from the joints below
        bool clash = false;
        for (double j : below)
          if (std::abs(end + 0.5 * gap - j) < min_offset) clash = true;
        if (!clash) break;
        end += min_offset;
      }
      if (end > pk.x1 - min_len) {
        spans.push_back({x, pk.x1});
        break;
      }
      spans.push_back({x, end});
      joints.push_back(end + 0.5 * gap);
      x = end + gap;
    }
    for (auto [a, b] : spans) {
      if (b - a < 3.0 * chamfer) continue;
      Polygon p{Vec2(a, y), Vec2(b, y), Vec2(b, y + h - chamfer), Vec2(b - chamfer, y + h),
                Vec2(a + chamfer, y + h), Vec2(a, y + h - chamfer)};
      pk.cells.push_back(p);
    }
    below = joints;
    pk.top = y + h;
    y += h - squeeze;
  }
  return pk;
}

// Convex polygon moved inward by r (each edge offset along its inward normal): the Minkowski sum
// of the result with a disk of radius r is the polygon with its corners rounded by r, which is
// what rockdem's rounding length r does to the same polygon.
Polygon inset(const Polygon& p, double r) {
  const std::size_t k = p.size();
  Polygon out(k);
  for (std::size_t i = 0; i < k; ++i) {
    const Vec2& prev = p[(i + k - 1) % k];
    const Vec2& cur = p[i];
    const Vec2& next = p[(i + 1) % k];
    const Vec2 n0 = perp((cur - prev).normalized());  // inward (left) normal of a ccw polygon
    const Vec2 n1 = perp((next - cur).normalized());
    out[i] = cur + r * (n0 + n1) / (1.0 + n0.dot(n1));
  }
  return out;
}

struct ContactParams {
  double kn = 10e9, ks = 5e9, friction_deg = 30.0, density = 2650.0;
  double rounding = 1e-3, tolerance = 1e-3;
};

// Build the rockdem model: blocks (group 0) on a fixed base block (group 1).
std::unique_ptr<Model> build_contact_model(const Packing& pk, const ContactParams& cp, std::vector<int>& walls) {
  auto m = std::make_unique<Model>();
  m->gravity = Vec2(0.0, -9.81);
  m->contacts.rounding = cp.rounding;
  char kn[64], ks[64], fr[64];
  std::snprintf(kn, sizeof kn, "%.17g Pa/m", cp.kn);
  std::snprintf(ks, sizeof ks, "%.17g Pa/m", cp.ks);
  std::snprintf(fr, sizeof fr, "%.17g deg", cp.friction_deg);
  m->contacts.models.push_back(make_joint_model("coulomb_slip", vals({{"kn", kn}, {"ks", ks}, {"friction", fr}}), {}, "bench"));
  m->contacts.model_names.push_back("joint");
  m->contacts.assignments.push_back({-1, -1, 0});
  int id = 0;
  for (const Polygon& c : pk.cells) add_rigid_block(*m, c, cp.density, "cell" + std::to_string(id++), 0);
  const double T = 0.2;
  walls.clear();
  walls.push_back(add_rigid_block(*m, Polygon{Vec2(pk.x0 - T, pk.y0 - T), Vec2(pk.x1 + T, pk.y0 - T), Vec2(pk.x1 + T, pk.y0),
                                              Vec2(pk.x0 - T, pk.y0)},
                                  cp.density, "base", 1));
  return m;
}

void add_walls(Engine& e, const Model& m, const std::vector<int>& walls) {
  for (int b : walls) {
    FaceSelection sel;
    sel.block = b;
    sel.points = m.blocks[b].boundary;
    e.add_condition(std::make_unique<FixedCondition>(sel, true, true, true));
  }
}

struct ContactCount {
  std::size_t items = 0, touching = 0, pairs = 0;
};
ContactCount count_contacts(const Model& m) {
  ContactCount cc;
  cc.items = m.contacts.items.size();
  std::set<std::pair<int, int>> pairs;
  for (const Contact& c : m.contacts.items) {
    if (c.response.open || c.pretouch_gap > 0.0 || c.overlap <= 0.0) continue;
    ++cc.touching;
    const int a = id_value(std::min(c.key.point_block, c.key.other_block)), b = id_value(std::max(c.key.point_block, c.key.other_block));
    pairs.insert({a, b});
  }
  cc.pairs = pairs.size();
  return cc;
}

void write_lammps(const std::string& dir, const Packing& pk, const ContactParams& cp, double dt, long steps,
                  double k_n, double c_n, double c_t) {
  std::filesystem::create_directories(dir);
  std::size_t nmax = 0;
  for (const auto& c : pk.cells) nmax = std::max(nmax, c.size());
  const double T = 0.2;
  {
    std::ofstream f(dir + "/packing.data");
    f << std::setprecision(17);
    f << "rockdem bench packing: " << pk.cells.size()
      << " rounded polygons (rockdem polygons inset by the rounding radius), SI units, per metre thickness\n\n";
    f << pk.cells.size() << " atoms\n" << pk.cells.size() << " bodies\n1 atom types\n\n";
    f << pk.x0 - T << " " << pk.x1 + T << " xlo xhi\n" << pk.y0 - T << " " << pk.top + 2.0 * pk.height << " ylo yhi\n-0.5 0.5 zlo zhi\n\n";
    f << "Atoms # body\n\n";
    // atom-ID atom-type bodyflag mass x y z (mass per metre thickness; inertia below likewise)
    for (std::size_t i = 0; i < pk.cells.size(); ++i) {
      const Vec2 g = polygon_centroid(pk.cells[i]);
      const double mass = cp.density * std::abs(signed_area(pk.cells[i]));
      f << i + 1 << " 1 1 " << mass << " " << g.x() << " " << g.y() << " 0\n";
    }
    f << "\nBodies\n\n";
    for (std::size_t i = 0; i < pk.cells.size(); ++i) {
      const Polygon& c = pk.cells[i];
      const Vec2 g = polygon_centroid(c);
      const SecondMoments sm = second_moments(c);
      const Polygon in = inset(c, cp.rounding);
      // ID Ninteger Ndouble / Nvertices / Ixx Iyy Izz Ixy Ixz Iyz / vertex displacements from the
      // centre of mass / rounded diameter. The same rockdem polygon's inertia (about its own
      // centroid); in-plane components as a lamina: Ixx = rho*int y^2, Iyy = rho*int x^2,
      // Ixy = -rho*int xy, Izz = Ixx + Iyy.
      f << i + 1 << " 1 " << 6 + 3 * in.size() + 1 << "\n" << in.size() << "\n";
      f << cp.density * sm.ixx << " " << cp.density * sm.iyy << " " << cp.density * sm.polar() << " " << -cp.density * sm.ixy << " 0 0\n";
      for (const Vec2& v : in) f << v.x() - g.x() << " " << v.y() - g.y() << " 0\n";
      f << 2.0 * cp.rounding << "\n";
    }
  }
  {
    std::ofstream f(dir + "/in.packing");
    f << std::setprecision(17);
    f << "# rockdem bench packing in LAMMPS (written by rockdem_bench_engine contacts --lammps)\n"
      << "# same polygons (inset by the rounding radius, rounded diameter 2r), positions, masses,\n"
      << "# gravity, friction, time step and step count as the rockdem run.\n"
      << "variable steps index " << steps << "\n"
      << "units si\ndimension 2\nboundary f f p\n"
      << "atom_style body rounded/polygon 1 " << nmax << "\natom_modify map array\n"
      << "read_data " << dir << "/packing.data\n"
      << "# c_n c_t mu delta_ua cut_inner; k_n k_na (no cohesion)\n"
      << "pair_style body/rounded/polygon " << c_n << " " << c_t << " " << std::tan(cp.friction_deg * std::numbers::pi / 180.0)
      << " 1.0 " << cp.tolerance << "\n"
      << "pair_coeff * * " << k_n << " 0.0\n"
      << "comm_modify vel yes\n"
      << "neighbor " << 0.1 * pk.height << " bin\nneigh_modify every 1 delay 0 check yes\n"
      << "timestep " << dt << "\n"
      << "fix 1 all nve/body\nfix 2 all enforce2d\n"
      << "# the base: a wall at y = " << pk.y0 << " (rockdem: a fixed rigid block)\n"
      << "fix 3 all wall/body/polygon " << k_n << " " << c_n << " " << c_t << " yplane " << pk.y0 << " NULL\n"
      << "fix 5 all gravity 9.81 vector 0 -1 0\n"
      << "thermo_style custom step ke pe\nthermo ${steps}\n"
      << "run ${steps}\n";
  }
}

int bench_contacts(const Args& a) {
  const int rows = static_cast<int>(a.num("rows", 50));
  const double width = a.num("width", 12.0);
  const long steps = static_cast<long>(a.num("steps", 2000));
  const int reps = static_cast<int>(a.num("reps", 3));
  const auto seed = static_cast<std::uint64_t>(a.num("seed", 20261121));
  const double squeeze = a.num("squeeze", 2e-5);
  const long chunk = std::max(1L, static_cast<long>(a.num("chunk", static_cast<double>(steps))));
  ContactParams cp;
  const Packing pk = make_packing(rows, width, seed, squeeze);
  std::size_t nv = 0;
  for (const auto& c : pk.cells) nv += c.size();
  std::printf("packing: %zu blocks (%zu vertices; %d courses of height %.3f m, %.2f m wide), seed %llu, bed-joint squeeze %.1e m\n",
              pk.cells.size(), nv, rows, pk.height, pk.x1 - pk.x0, static_cast<unsigned long long>(seed), squeeze);

  // The time step: rockdem's automatic stable step on this packing, rounded down to 2 digits,
  // then fixed for the timed runs (and given to LAMMPS). Also the mean contact length, for the
  // LAMMPS point stiffness.
  double dt = 0.0, mean_length = 0.0;
  {
    std::vector<int> walls;
    auto m = build_contact_model(pk, cp, walls);
    EngineSettings s;
    s.threads = static_cast<int>(a.num("threads", 1));
    s.detection.distance = cp.rounding + cp.tolerance;
    Engine e(*m, s);
    add_walls(e, *m, walls);
    e.begin_stage("dt", Damping{});
    const double p = std::pow(10.0, std::floor(std::log10(e.dt())) - 1);
    dt = std::floor(e.dt() / p) * p;
    std::size_t n = 0;
    for (const Contact& c : m->contacts.items)
      if (!c.response.open && c.pretouch_gap <= 0.0 && c.overlap > 0.0) {
        mean_length += c.length;
        ++n;
      }
    mean_length /= static_cast<double>(std::max<std::size_t>(n, 1));
    std::printf("automatic stable time step %.4e s -> fixed dt %.3e s; mean contact length %.4f m\n", e.dt(), dt, mean_length);
  }
  if (const std::string dir = a.str("lammps", ""); !dir.empty()) {
    // LAMMPS point stiffness: a rockdem contact point is a spring kn * (its contact length); a
    // body/rounded/polygon vertex-edge contact is a spring k_n. So k_n = kn * mean length, and
    // a bed joint (two contact points in both codes) has the same stiffness on average.
    const double k_n = cp.kn * mean_length;
    double mass = 0.0;
    for (const auto& c : pk.cells) mass += cp.density * std::abs(signed_area(c));
    mass /= static_cast<double>(pk.cells.size());
    const double c_crit = 2.0 * std::sqrt(k_n * mass);
    write_lammps(dir, pk, cp, dt, steps, k_n, 0.1 * c_crit, 0.1 * c_crit);
    std::printf("LAMMPS files: %s/packing.data, %s/in.packing (k_n %.4e N/m, c_n = c_t = %.4e N s/m, dt %.3e s, %ld steps)\n",
                dir.c_str(), dir.c_str(), k_n, 0.1 * c_crit, dt, steps);
  }
  std::vector<double> rates, cpu_rates;
  for (int r = 0; r < reps; ++r) {
    std::vector<int> walls;
    auto m = build_contact_model(pk, cp, walls);
    EngineSettings s;
    s.threads = static_cast<int>(a.num("threads", 1));
    s.detection.distance = cp.rounding + cp.tolerance;
    s.fixed_dt = dt;
    Engine e(*m, s);
    add_walls(e, *m, walls);
    e.begin_stage("bench", Damping{});
    const ContactCount c0 = count_contacts(*m);
    const auto t0 = Clock::now();
    const std::clock_t cpu0 = std::clock();
    for (long done = 0; done < steps; done += chunk) e.run_steps(std::min(chunk, steps - done));
    const double cpu = static_cast<double>(std::clock() - cpu0) / CLOCKS_PER_SEC;
    const double sec = std::chrono::duration<double>(Clock::now() - t0).count();
    const ContactCount c1 = count_contacts(*m);
    const double cs = static_cast<double>(c0.touching) * static_cast<double>(steps) / sec;
    rates.push_back(cs);
    cpu_rates.push_back(static_cast<double>(c0.touching) * static_cast<double>(steps) / cpu);
    std::printf("contacts rep %d: %zu blocks; contact points %zu (touching %zu, block pairs touching %zu) at start, "
                "%zu (touching %zu, pairs %zu) at end; %ld steps in %.3f s = %.1f steps/s -> %.3e contact-steps/s, "
                "%.1f ns per contact-step\n",
                r + 1, m->blocks.size(), c0.items, c0.touching, c0.pairs, c1.items, c1.touching, c1.pairs, steps, sec,
                static_cast<double>(steps) / sec, cs, 1e9 / cs);
    std::printf("RESULT kind=contacts rep=%d blocks=%zu contacts=%zu touching=%zu pairs=%zu steps=%ld dt=%.6e seconds=%.6f "
                "cpu_seconds=%.6f contact_steps_per_s=%.6e\n",
                r + 1, m->blocks.size(), c0.items, c0.touching, c0.pairs, steps, dt, sec, cpu, cs);
  }
  std::printf("contacts median: %.3e contact-steps/s per core (wall time), %.3e (process CPU time)\n", median(rates), median(cpu_rates));
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2 || (std::string(argv[1]) != "zones" && std::string(argv[1]) != "contacts")) {
    std::fprintf(stderr, "usage: %s zones|contacts [--key value ...]  (see the header of scripts/bench/bench_engine.cpp)\n", argv[0]);
    return 2;
  }
  Args a;
  for (int i = 2; i + 1 < argc; i += 2) {
    std::string k = argv[i];
    if (k.rfind("--", 0) != 0) {
      std::fprintf(stderr, "expected --key value, got '%s'\n", argv[i]);
      return 2;
    }
    a.kv[k.substr(2)] = argv[i + 1];
  }
  try {
    return std::string(argv[1]) == "zones" ? bench_zones(a) : bench_contacts(a);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
}
