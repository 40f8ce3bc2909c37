// Viscous (quiet) boundary (Lysmer & Kuhlemeyer 1969): a compressional pulse sent down a laterally
// confined elastic column must leave through a quiet base, while a fixed base reflects it back.
// Cp = sqrt((K + 4G/3) / rho) = 4003 m/s; the 10 m column is crossed in 2.5 ms, the 0.5 ms half-sine pulse
// has left the column by 3 ms. At 4 ms a fixed base has sent the pulse back up (kinetic energy
// about half of the pulse's energy), a quiet one has absorbed it.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <unistd.h>
#include <iostream>

#include "framework/simulation/run_case.hpp"

using namespace rockdem;

namespace {

double kinetic_energy_ratio(const std::string& base) {
  const std::string text = std::string(R"TOML(
title = "pulse in a confined column"
[[materials]]
name = "rock"
model = "elastic"
density = "2420 kg/m3"
bulk = "20 GPa"
shear = "14 GPa"
[[blocks]]
name = "column"
type = "deformable"
material = "rock"
rectangle = ["0 m", "0 m", "0.5 m", "10 m"]
zones = [2, 80]
[[boundary]]
type = "fixed"
block = "column"
face = "left"
components = ["x"]
[[boundary]]
type = "fixed"
block = "column"
face = "right"
components = ["x"]
[[boundary]]
type = "traction"
block = "column"
face = "top"
normal = { expression = { value = "(t < 0.0005) * sin(pi * t / 0.0005)", unit = "MPa" } }
)TOML") + base + R"TOML(
[[stages]]
name = "wave"
damping = "none"
until = "duration"
duration = "4 ms"
[[histories]]
name = "ke"
quantity = "kinetic_energy"
[output]
history_interval = 5
)TOML";
  Case c = load_case_text(text, "quiet-boundary test", ".");
  const auto out = std::filesystem::temp_directory_path() / ("rockdem_test_quiet_" + std::to_string(::getpid()));
  RunResult r = run_case(c, out, true);
  std::filesystem::remove_all(out);
  const auto ke = r.history.values(r.history.id("ke"));
  const auto t = r.history.times();
  double peak = 0.0, late = 0.0;
  for (std::size_t i = 0; i < ke.size(); ++i) {
    if (t[i] < 1.5e-3) peak = std::max(peak, ke[i]);  // the pulse travelling down, whole
    if (t[i] > 3.8e-3) late = std::max(late, ke[i]);
  }
  return late / peak;
}

}  // namespace

TEST(QuietBoundary, AbsorbsAPulseThatAFixedBaseReflects) {
  const double quiet = kinetic_energy_ratio("[[boundary]]\ntype = \"quiet\"\nblock = \"column\"\nface = \"bottom\"\n");
  const double fixed = kinetic_energy_ratio("[[boundary]]\ntype = \"fixed\"\nblock = \"column\"\nface = \"bottom\"\n");
  std::cout << "kinetic energy after the pulse reached the base / while travelling: quiet " << quiet << ", fixed "
            << fixed << "\n";
  EXPECT_LT(quiet, 0.01);
  EXPECT_GT(fixed, 0.5);
}
