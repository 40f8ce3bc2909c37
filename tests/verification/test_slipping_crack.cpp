// Elastic block with an inclined, closed crack under one uniaxial load cycle (Olsson 1982; the
// UDEC/3DEC verification problem, after the conceptual model of Brady et al. 1985): the crack
// crosses the block at alpha = 45 deg to the load, its middle portion slips (phi = 16 deg), the
// rest of it stays elastic. Loading, the portion slips forward (tau = sigma_n tan phi); unloading,
// it locks, and slips back once tau = -sigma_n tan phi. With the crack's normal and shear
// stresses proportional to the load as sigma_n ~ cos(alpha), tau ~ sin(alpha) (the whole load
// crosses the crack plane) this happens at F_B / F_A = sin(alpha - phi) / sin(alpha + phi)
// = 0.554309, whatever the stiffnesses.
// The load is a normal stress on the top face (so F is known exactly): 0 -> 10 MPa -> 0, each way
// in 20,000 mass-scaled, locally damped steps. F_B is where the mean shear over the mean normal
// stress of the slipping portion first reaches -tan(phi) (the portion as a whole slips back, as in
// the conceptual model); the first and the last of its contacts to slip back are printed too.
// The damped model lags the load a little, so F_B depends on the load rate (0.5670 with 20 s each
// way, 0.5623 with 40 s, 0.5597 with 80 s: the difference halves with the rate, a first-order lag).
// The test runs the cycle at 20 s and at 40 s each way and compares the quasi-static value,
// extrapolated as 2 F_B(40 s) - F_B(20 s), with the closed form.
// Case file and numbers: cases/verification/slipping_crack/README.md.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <numbers>
#include <sstream>
#include <string>
#include <unistd.h>

#include "framework/simulation/run_case.hpp"

using namespace rockdem;

namespace {

struct Reversal {
  double b_mean = -1, b_first = -1, b_all = -1, locked_from = -1;
};

// Runs crack.toml with each way of the cycle lasting `ramp` seconds (its 20 s replaced in the
// stages' durations and the load expressions) and checks the loading branch.
Reversal run_cycle(double ramp, double phi) {
  const std::string src = std::string(ROCKDEM_SOURCE_DIR) + "/cases/verification/slipping_crack/crack.toml";
  std::ifstream in(src);
  std::stringstream text;
  text << in.rdbuf();
  std::string toml = text.str();
  const std::string r = std::to_string(static_cast<int>(ramp));
  auto replace_all = [&](const std::string& from, const std::string& to) {
    int n = 0;
    for (std::size_t at = toml.find(from); at != std::string::npos; at = toml.find(from, at + to.size()), ++n)
      toml.replace(at, from.size(), to);
    return n;
  };
  EXPECT_EQ(replace_all("t / 20)", "t / " + r + ")"), 1);
  EXPECT_EQ(replace_all("t / 20\"", "t / " + r + "\""), 1);
  EXPECT_EQ(replace_all("duration = \"20 s\"", "duration = \"" + r + " s\""), 2);
  const auto dir = std::filesystem::temp_directory_path() / ("rockdem_test_crack_" + std::to_string(::getpid()) + "_" + r);
  std::filesystem::create_directories(dir);
  const auto file = dir / "crack.toml";
  std::ofstream(file) << toml;
  Case c = load_case(file.string());
  RunResult res = run_case(c, dir / "out", true);
  std::filesystem::remove_all(dir);
  const History& h = res.history;
  const auto t = h.times();
  const auto stage = h.values(h.id("stage")), frac = h.values(h.id("slip_fraction"));
  const auto sn = h.values(h.id("sn")), tau = h.values(h.id("tau"));
  const double sigma_a = 10e6;  // Pa, as in the case file
  const auto load = [&](std::size_t i) { return stage[i] == 1 ? sigma_a * t[i] / ramp : sigma_a * (1 - (t[i] - ramp) / ramp); };

  // Loading: the portion slips forward, tau / sigma_n = tan(phi) (one of its 11 contacts now and then
  // sticks for a few samples as the damped model follows the load).
  for (std::size_t i = 0; i < t.size(); ++i)
    if (stage[i] == 1 && load(i) > 0.1 * sigma_a) {
      EXPECT_NEAR(tau[i] / sn[i], std::tan(phi), 1e-3 * std::tan(phi)) << "t = " << t[i];
      EXPECT_GT(frac[i], 0.85) << "t = " << t[i];
    }
  // Unloading: after the reversal (the damped model follows the load within 0.5 s), locked, then
  // slipping back.
  Reversal rv;
  for (std::size_t i = 0; i < t.size(); ++i) {
    if (stage[i] != 2 || t[i] < ramp + 0.5) continue;
    const double f = load(i) / sigma_a;
    if (rv.locked_from < 0 && frac[i] == 0.0) rv.locked_from = f;
    if (rv.locked_from < 0) continue;
    if (rv.b_first < 0 && frac[i] > 0.0) rv.b_first = f;
    if (rv.b_all < 0 && frac[i] > 0.999) rv.b_all = f;
    if (rv.b_mean < 0 && tau[i] / sn[i] <= -std::tan(phi) * (1 - 1e-3)) rv.b_mean = f;
  }
  std::cout << "slipping crack, " << ramp << " s each way: F_B/F_A = " << rv.b_mean << " (portion as a whole); first contact back "
            << rv.b_first << ", all back " << rv.b_all << "; locked from " << rv.locked_from << "\n";
  EXPECT_GT(rv.locked_from, 0.95);  // locked right after the reversal
  EXPECT_GE(rv.b_first, rv.b_mean);
  EXPECT_LE(rv.b_all, rv.b_mean);
  return rv;
}

}  // namespace

TEST(SlippingCrack, ReverseSlipStartsAtTheClosedFormLoadRatio) {
  const double deg = std::numbers::pi / 180, alpha = 45 * deg, phi = 16 * deg;
  const double closed = std::sin(alpha - phi) / std::sin(alpha + phi);
  EXPECT_NEAR(closed, 0.554309, 5e-7);
  const Reversal fast = run_cycle(20.0, phi), slow = run_cycle(40.0, phi);
  // The slower cycle is nearer the quasi-static value, and the lag is first order in the rate.
  EXPECT_LT(std::abs(slow.b_mean - closed), std::abs(fast.b_mean - closed) + 1e-3);
  const double quasi_static = 2 * slow.b_mean - fast.b_mean;
  std::cout << "slipping crack: quasi-static F_B/F_A = " << quasi_static << " (closed form " << closed << ", error "
            << (quasi_static / closed - 1) * 100 << " %)\n";
  EXPECT_NEAR(quasi_static, closed, 0.01 * closed);
}
