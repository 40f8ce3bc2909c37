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
// Case file and numbers: cases/verification/slipping_crack/README.md.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <iostream>
#include <numbers>
#include <string>
#include <unistd.h>

#include "framework/simulation/run_case.hpp"

using namespace rockdem;

TEST(SlippingCrack, ReverseSlipStartsAtTheClosedFormLoadRatio) {
  const double deg = std::numbers::pi / 180, alpha = 45 * deg, phi = 16 * deg;
  const double closed = std::sin(alpha - phi) / std::sin(alpha + phi);
  EXPECT_NEAR(closed, 0.554309, 5e-7);

  Case c = load_case(std::string(ROCKDEM_SOURCE_DIR) + "/cases/verification/slipping_crack/crack.toml");
  const auto out = std::filesystem::temp_directory_path() / ("rockdem_test_crack_" + std::to_string(::getpid()));
  RunResult r = run_case(c, out, true);
  std::filesystem::remove_all(out);
  const History& h = r.history;
  const auto t = h.times();
  const auto stage = h.values(h.id("stage")), frac = h.values(h.id("slip_fraction"));
  const auto sn = h.values(h.id("sn")), tau = h.values(h.id("tau"));
  const double sigma_a = 10e6, ramp = 20.0;  // Pa, s: as in the case file
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
  double b_mean = -1, b_first = -1, b_all = -1, locked_from = -1;
  for (std::size_t i = 0; i < t.size(); ++i) {
    if (stage[i] != 2 || t[i] < ramp + 0.5) continue;
    const double f = load(i) / sigma_a;
    if (locked_from < 0 && frac[i] == 0.0) locked_from = f;
    if (locked_from < 0) continue;
    if (b_first < 0 && frac[i] > 0.0) b_first = f;
    if (b_all < 0 && frac[i] > 0.999) b_all = f;
    if (b_mean < 0 && tau[i] / sn[i] <= -std::tan(phi) * (1 - 1e-3)) b_mean = f;
  }
  std::cout << "slipping crack: F_B/F_A = " << b_mean << " (portion as a whole; closed form " << closed << ", error "
            << (b_mean / closed - 1) * 100 << " %); first contact back " << b_first << ", all back " << b_all
            << "; locked from " << locked_from << "\n";
  EXPECT_GT(locked_from, 0.95);  // locked right after the reversal
  EXPECT_NEAR(b_mean, closed, 0.01 * closed);
  EXPECT_GE(b_first, b_mean);
  EXPECT_LE(b_all, b_mean);
}
