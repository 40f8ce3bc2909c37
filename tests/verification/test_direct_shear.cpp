// The report's direct-shear specimen (Figure 4-7 model, test 9 at 3 MPa) with a Coulomb slip
// joint: after the elastic rise the loading-block shear stress must sit on sigma_n tan(phi) =
// 3 tan 38 = 2.3439 MPa along the stroke, forward and back, with no edge-contact artefact (the
// report's Figure 4-4: a contact length shrinking to zero at the specimen edge made the shear
// stress there grow without bound). And the laboratory rate with mass scaling must give the same
// curve as 100 mm/s.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <unistd.h>
#include <iostream>
#include <numbers>

#include "framework/simulation/run_case.hpp"

using namespace rockdem;

namespace {

const double kPlateau = 3.0 * std::tan(38.0 * std::numbers::pi / 180.0);  // MPa

struct Branch {
  std::vector<double> us, tau;  // shear displacement [mm], shear stress [MPa]
};

// Forward (us increasing) and reverse branches of the joint record.
std::pair<Branch, Branch> run(const std::string& file, const std::string& tag) {
  Case c = load_case(std::string(ROCKDEM_SOURCE_DIR) + "/cases/direct_shear/" + file);
  const auto out = std::filesystem::temp_directory_path() / ("rockdem_test_ds_" + tag + "_" + std::to_string(::getpid()));
  RunResult r = run_case(c, out, true);
  std::filesystem::remove_all(out);
  Branch f, b;
  const auto& rows = r.lab.rows;
  for (std::size_t i = 1; i < rows.size(); ++i) {
    Branch& br = rows[i].shear_disp_mm >= rows[i - 1].shear_disp_mm ? f : b;
    br.us.push_back(rows[i].shear_disp_mm);
    br.tau.push_back(rows[i].shear_stress_MPa);
  }
  return {f, b};
}

struct Stats {
  double mean = 0, max_dev = 0, frac_within_1pct = 0;
};

// Sliding part of a branch: more than 2 mm from both ends of the stroke.
Stats plateau(const Branch& br) {
  Stats s;
  int n = 0, ok = 0;
  for (std::size_t i = 0; i < br.us.size(); ++i) {
    if (br.us[i] < 2.0 || br.us[i] > 38.0) continue;
    const double dev = std::abs(std::abs(br.tau[i]) - kPlateau) / kPlateau;
    s.mean += std::abs(br.tau[i]);
    s.max_dev = std::max(s.max_dev, dev);
    ok += dev <= 0.01;
    ++n;
  }
  s.mean /= n;
  s.frac_within_1pct = static_cast<double>(ok) / n;
  return s;
}

double interp(const Branch& br, double u) {
  // Branches are monotonic in us (increasing forward, decreasing reverse).
  for (std::size_t i = 1; i < br.us.size(); ++i) {
    const double a = br.us[i - 1], b = br.us[i];
    if ((u - a) * (u - b) <= 0.0 && a != b) return br.tau[i - 1] + (br.tau[i] - br.tau[i - 1]) * (u - a) / (b - a);
  }
  return NAN;
}

void check_plateaus(const std::pair<Branch, Branch>& r, const std::string& what) {
  for (const auto* br : {&r.first, &r.second}) {
    const Stats s = plateau(*br);
    const char* dir = br == &r.first ? "forward" : "reverse";
    std::cout << what << " " << dir << ": mean |tau| " << s.mean << " MPa (sigma_n tan phi = " << kPlateau
              << "), max deviation " << 100 * s.max_dev << " %, " << 100 * s.frac_within_1pct
              << " % of samples within 1 %\n";
    // The plateau: its mean within 0.2 %, 99 % of the samples within 1 %. The few samples beyond
    // are short transients (< 0.2 mm of slip) when a specimen corner passes a gridpoint of the
    // other block, bounded here at 4 %; they shrink with the zone size.
    EXPECT_NEAR(s.mean, kPlateau, 0.002 * kPlateau) << what << " " << dir;
    EXPECT_GE(s.frac_within_1pct, 0.99) << what << " " << dir;
    EXPECT_LT(s.max_dev, 0.04) << what << " " << dir;
  }
  // Elastic rise: stiffness-limited, reaches the plateau within the first 1 mm.
  EXPECT_GT(interp(r.first, 1.0), 0.98 * kPlateau);
}

}  // namespace

TEST(DirectShear, CoulombPlateauAt100mmPerSecondAndLabRateAgree) {
  const auto fast = run("test09_coulomb.toml", "fast");
  check_plateaus(fast, "100 mm/s");
  const auto lab = run("test09_coulomb_labrate.toml", "lab");
  check_plateaus(lab, "4.2e-5 m/s (mass scaled)");
  // Same curve at both rates: mean absolute difference on both branches below 0.5 % of the plateau.
  double diff = 0.0;
  int n = 0;
  for (double u = 2.0; u <= 38.0; u += 0.25) {
    diff += std::abs(interp(fast.first, u) - interp(lab.first, u)) + std::abs(interp(fast.second, u) - interp(lab.second, u));
    n += 2;
  }
  diff /= n;
  std::cout << "mean |tau(100 mm/s) - tau(lab rate)| = " << diff << " MPa\n";
  EXPECT_LT(diff, 0.005 * kPlateau);
}
