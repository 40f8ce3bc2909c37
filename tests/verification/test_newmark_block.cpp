// Newmark (1965) sliding block through the whole engine: a rigid block on a horizontal rigid base
// (Coulomb joint, tan(phi) = mu = 0.2), the base driven by a `velocity` condition.
// 1. Rectangular base acceleration pulse A = 0.5 g for t0 = 0.2 s: the block slides at a_y = mu g
//    until its velocity catches up with the base's, u = V^2 / (2 a_y) (1 - a_y / A), V = A t0:
//    0.14715 m (g = 9.81 m/s2).
// 2. The El Centro 1940 N-S record (scaled by 2): the base velocity is the record integrated
//    (framework/seismic/signal_processing), handed to both the engine (as a velocity table) and an
//    independent rigid-plastic integration of the same base motion written below. On a horizontal
//    base the block slips both ways (the yield acceleration is mu g either way), so the integrator
//    is two-way.
// Case file and numbers: cases/verification/newmark_block/README.md.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <unistd.h>
#include <vector>

#include "framework/seismic/ground_motion.hpp"
#include "framework/seismic/signal_processing.hpp"
#include "framework/simulation/run_case.hpp"

using namespace rockdem;

namespace {

const std::string kDir = std::string(ROCKDEM_SOURCE_DIR) + "/cases/verification/newmark_block/";
constexpr double kG = 9.81, kMu = 0.2;

std::string read_text(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// Replaces the one line of `text` that starts with `start` (the case file is the reference; the
// record variant changes only the drive and the duration).
std::string replace_line(std::string text, const std::string& start, const std::string& line) {
  const auto p = text.find("\n" + start);
  EXPECT_NE(p, std::string::npos) << start;
  if (p == std::string::npos) return text;
  const auto e = text.find('\n', p + 1);
  return text.replace(p + 1, e - p - 1, line);
}

struct Slip {
  std::vector<double> t, u;  // stage time, block x minus base x since the stage start
};

Slip run(const std::string& text, const std::string& name) {
  Case c = load_case_text(text, name, ".");
  const auto out = std::filesystem::temp_directory_path() / ("rockdem_test_newmark_" + name + "_" + std::to_string(::getpid()));
  RunResult r = run_case(c, out, true);
  std::filesystem::remove_all(out);
  const History& h = r.history;
  const auto stage = h.values(h.id("stage"));
  const auto bx = h.values(h.id("block_x")), gx = h.values(h.id("base_x"));
  Slip s;
  double t0 = -1, u0 = 0;
  for (std::size_t i = 0; i < h.sample_count(); ++i) {
    if (stage[i] != 2) continue;
    if (t0 < 0) {
      t0 = h.times()[i];
      u0 = bx[i] - gx[i];
    }
    s.t.push_back(h.times()[i] - t0);
    s.u.push_back(bx[i] - gx[i] - u0);
  }
  return s;
}

double interp(const std::vector<double>& t, const std::vector<double>& y, double x) {
  if (x <= t.front()) return y.front();
  const auto it = std::upper_bound(t.begin(), t.end(), x);
  if (it == t.end()) return y.back();
  const std::size_t i = static_cast<std::size_t>(it - t.begin());
  return y[i - 1] + (y[i] - y[i - 1]) * (x - t[i - 1]) / (t[i] - t[i - 1]);
}

// Rigid-plastic block on a horizontal base whose velocity is linear between the samples vb[k]
// (spacing dt), i.e. a piecewise-constant base acceleration. Relative velocity w = v_block - v_base:
// sliding, w' = -mu g sign(w) - a_base; stuck (w = 0), it stays stuck while |a_base| <= mu g, else
// slides the way the base leaves it. Each interval is integrated exactly (w is piecewise linear), with
// the stop at w = 0 inside an interval found exactly. Returns the relative displacement at the samples.
std::vector<double> newmark_two_way(const std::vector<double>& vb, double dt, double ay) {
  std::vector<double> u(vb.size(), 0.0);
  double w = 0.0, x = 0.0;
  for (std::size_t k = 0; k + 1 < vb.size(); ++k) {
    const double ab = (vb[k + 1] - vb[k]) / dt;
    double left = dt;
    while (left > 0.0) {
      if (w == 0.0) {
        if (std::abs(ab) <= ay) break;  // stuck for the rest of the interval
        const double a = (ab > 0 ? ay : -ay) - ab;  // block pulled at ay towards the base's way
        x += 0.5 * a * left * left;
        w = a * left;
        left = 0.0;
        break;
      }
      const double a = (w > 0 ? -ay : ay) - ab;
      const double stop = (w * a < 0.0) ? -w / a : 1e300;  // time until w = 0
      if (stop >= left) {
        x += w * left + 0.5 * a * left * left;
        w += a * left;
        left = 0.0;
      } else {
        x += w * stop + 0.5 * a * stop * stop;
        w = 0.0;
        left -= stop;
      }
    }
    u[k + 1] = x;
  }
  return u;
}

}  // namespace

TEST(NewmarkBlock, RectangularPulseMatchesClosedForm) {
  const double A = 0.5 * kG, t0 = 0.2, ay = kMu * kG, V = A * t0;
  const double closed = V * V / (2 * ay) * (1 - ay / A);  // 0.14715 m
  const Slip s = run(read_text(kDir + "pulse.toml"), "pulse");
  const double u = -s.u.back();  // the base moves +x, the block lags behind it
  std::cout << "Newmark pulse: slip " << u << " m (closed form " << closed << ", error "
            << (u / closed - 1) * 100 << " %)\n";
  EXPECT_NEAR(closed, 0.14715, 1e-5);
  EXPECT_NEAR(u, closed, 0.01 * closed);
  // It has stopped: the slip at 0.7 s (0.2 s after the block caught up at 0.5 s) is the final one.
  EXPECT_NEAR(-interp(s.t, s.u, 0.7), u, 1e-4 * closed);
}

TEST(NewmarkBlock, RecordMatchesIndependentIntegration) {
  seismic::RecordLayout layout;
  layout.unit = seismic::parse_acceleration_unit("g");
  auto gm = seismic::load_ground_motion(ROCKDEM_SOURCE_DIR "/cases/data/ground_motions/elcentro1940_ns_acc_g.csv", layout);
  // Scaled by 2 (peak 0.64 g) so that the block, yielding at 0.2 g, slips many times both ways.
  for (double& a : gm.acc) a *= 2.0;
  seismic::remove_polynomial_baseline(gm.acc, gm.dt, 1);
  std::vector<double> vb = seismic::integrate_trapezoid(gm.acc, gm.dt);
  vb.push_back(vb.back());  // two seconds at the final velocity: no acceleration, the block settles
  const double duration = gm.dt * static_cast<double>(vb.size() - 1) + 2.0;

  const auto table = std::filesystem::temp_directory_path() / ("rockdem_test_newmark_vel_" + std::to_string(::getpid()) + ".txt");
  {
    std::ofstream f(table);
    f.precision(17);
    f << "# El Centro 1940 N-S x 2, baseline removed, integrated: base velocity (s, m/s)\n";
    for (std::size_t k = 0; k < vb.size(); ++k) f << gm.dt * static_cast<double>(k) << " " << vb[k] << "\n";
  }
  std::string text = read_text(kDir + "pulse.toml");
  text = replace_line(text, "vx = { expression",
                      "vx = { file = { path = \"" + table.string() + "\", value_unit = \"m/s\" } }");
  text = replace_line(text, "duration = ", "duration = \"" + std::to_string(duration) + " s\"");
  const Slip s = run(text, "record");
  std::filesystem::remove(table);

  const std::vector<double> ref = newmark_two_way(vb, gm.dt, kMu * kG);
  // Sliding distance each way, summed (forward, back), of a slip history.
  const auto travel = [](const std::vector<double>& u) {
    std::pair<double, double> fb{0.0, 0.0};
    for (std::size_t k = 1; k < u.size(); ++k) (u[k] > u[k - 1] ? fb.first : fb.second) += std::abs(u[k] - u[k - 1]);
    return fb;
  };
  double peak = 0.0, worst = 0.0;
  for (std::size_t k = 0; k < ref.size(); ++k) {
    peak = std::max(peak, std::abs(ref[k]));
    worst = std::max(worst, std::abs(interp(s.t, s.u, gm.dt * static_cast<double>(k)) - ref[k]));
  }
  const auto [fwd, back] = travel(ref);
  const auto [dem_fwd, dem_back] = travel(s.u);
  const double fin = s.u.back(), ref_fin = ref.back();
  std::cout << "Newmark El Centro x2: slid " << dem_fwd << " m forward, " << dem_back << " m back (independent "
            << fwd << ", " << back << "; errors " << (dem_fwd / fwd - 1) * 100 << " %, " << (dem_back / back - 1) * 100
            << " %); final slip " << fin << " m (independent " << ref_fin << ", difference " << std::abs(fin - ref_fin)
            << " m); largest difference over the record " << worst << " m = " << worst / peak * 100
            << " % of the peak |slip| " << peak << " m\n";
  EXPECT_GT(std::min(fwd, back), 0.05);  // it slid, both ways
  // The slip history within 1 % of its peak at every sample of the record. The final net slip is the
  // difference of the two ways (a fifth of either), so its relative error is five times larger: it
  // is held to 1 % of the distance slid. The engine's distance slid each way (printed) is not tested:
  // it also counts the joint's elastic back-and-forth while stuck and the 10-step sampling.
  EXPECT_LT(worst, 0.01 * peak);
  EXPECT_NEAR(fin, ref_fin, 0.01 * (fwd + back));
}
