// A joint law gives the same answers through the element driver and through a DEM model: two
// stiff (rigid) blocks with one joint between them, the upper block under a 3 MPa traction and
// pushed by a rigid loading block through a frictionless interface (the report's Figure 4-2
// arrangement, in rigid form), against the element driver replaying the loader's displacement
// history under constant normal stress. Same law objects, same parameters.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <filesystem>
#include <string>
#include <unistd.h>

#include "framework/simulation/run_case.hpp"
#include "tests/unit/joint_law_test_util.hpp"

using namespace rockdem;
using namespace rockdem::testutil;

namespace {

// The DEM case with the joint's law and parameter lines spliced in.
std::string dem_case(const std::string& joint) {
  return R"(title = "two stiff blocks, one joint"
[model]
rounding = "0.5 mm"
detection_tolerance = "1 mm"
[time]
dt_safety = 0.5
refresh_interval = 10
[[joints]]
name = "joint"
between = ["bottom", "top"]
)" + joint + R"(
[[joints]]
name = "loading_interface"
law = "coulomb_slip"
between = ["loader", "top"]
kn = "200000 MPa/m"
ks = "20000 MPa/m"
friction = "0 deg"
tension = "10000 MPa"
residual_after_failure = false
[[blocks]]
name = "bottom"
type = "rigid"
density = "2418.8 kg/m3"
rectangle = ["-60 mm", "-100 mm", "420 mm", "100 mm"]
[[blocks]]
name = "top"
type = "rigid"
density = "2418.8 kg/m3"
rectangle = ["0 mm", "0 mm", "203.2 mm", "100 mm"]
[[blocks]]
name = "loader"
type = "rigid"
density = "2420 kg/m3"
rectangle = ["-20 mm", "6 mm", "20 mm", "88 mm"]
[[boundary]]
type = "fixed"
block = "bottom"
components = ["x", "y"]
[[boundary]]
type = "traction"
block = "top"
face = "top"
normal = "3 MPa"
[[boundary]]
type = "velocity"
block = "loader"
vx = "0 m/s"
vy = "0 m/s"
spin = "0 rad/s"
stages = ["consolidate"]
[[boundary]]
type = "velocity"
block = "loader"
vx = { cycles = { amplitude = "3 mm", speed = "10 mm/s", number = 1, one_sided = true } }
vy = "0 m/s"
spin = "0 rad/s"
stages = ["shear"]
[[stages]]
name = "consolidate"
damping = "local"
until = "equilibrium"
ratio = 1e-5
[[stages]]
name = "shear"
damping = "local"
until = "duration"
duration = "auto"
[direct_shear]
specimen = "two_blocks"
joint_length = "203.2 mm"
loader = "loader"
top = "top"
bottom = "bottom"
normal_stress = "3 MPa"
shear_stage = "shear"
[output]
history_interval = 20
)";
}

struct Compared {
  MeasurementFile dem, element;
};

Compared run_both(const std::string& law, const std::string& joint_lines, const RawValues& params) {
  const std::filesystem::path out =
      std::filesystem::temp_directory_path() / ("rockdem_dem_vs_element_" + law + "_" + std::to_string(::getpid()));
  Case c = load_case_text(dem_case("law = \"" + law + "\"\n" + joint_lines), "two-block case", ".");
  RunResult res = run_case(c, out, true);
  std::filesystem::remove_all(out);
  // The element driver replays the loader's displacement history at the DEM's sample times.
  std::vector<double> t, u;
  for (const auto& r : res.lab.rows) {
    t.push_back(r.time_s - res.lab.rows.front().time_s);
    u.push_back(r.shear_disp_mm * 1e-3);
  }
  auto m = model(law, params);
  ElementOptions o;
  o.length = 0.2032;
  o.max_step = 1e-6;
  ElementDriver d(*m, o);
  MeasurementFile el = d.run({cnl(3e6, ShearPath::table(t, u))});
  return {std::move(res.lab), std::move(el)};
}

// Largest |shear stress| on the forward and on the reverse stroke.
std::pair<double, double> peaks(const MeasurementFile& f) {
  double fwd = 0.0, rev = 0.0;
  for (const auto& r : f.rows) {
    fwd = std::max(fwd, r.shear_stress_MPa);
    rev = std::max(rev, -r.shear_stress_MPa);
  }
  return {fwd, rev};
}

// Mean shear stress over the forward stroke between two offsets [mm] (the slipping plateau).
double mean_tau_forward(const MeasurementFile& f, double from_mm, double to_mm) {
  double sum = 0.0;
  int n = 0;
  for (std::size_t i = 1; i < f.rows.size(); ++i) {
    const auto& r = f.rows[i];
    if (r.shear_disp_mm > f.rows[i - 1].shear_disp_mm && r.shear_disp_mm >= from_mm && r.shear_disp_mm <= to_mm) {
      sum += r.shear_stress_MPa;
      ++n;
    }
  }
  return n ? sum / n : 0.0;
}

double normal_disp_at_max_offset(const MeasurementFile& f) {
  std::size_t at = 0;
  for (std::size_t i = 0; i < f.rows.size(); ++i)
    if (f.rows[i].shear_disp_mm > f.rows[at].shear_disp_mm) at = i;
  return f.rows[at].normal_disp_mm;
}

}  // namespace

TEST(ElementVsDem, MohrCoulombTwoStiffBlocksMatchTheElementDriver) {
  const auto r = run_both("mohr_coulomb",
                          "kn = \"35.964 GPa/m\"\nks = \"16.93 GPa/m\"\nfriction = \"38 deg\"\n"
                          "dilation_angle = \"2.4 deg\"\ndilation = \"reversible\"\n",
                          mc_report({{"dilation", "reversible"}}));
  // The plateau (the DEM's first slip overshoots a little: inertia of the blocks).
  const double plateau = 3.0 * std::tan(38.0 * std::numbers::pi / 180.0);
  EXPECT_NEAR(mean_tau_forward(r.element, 1.0, 2.9), plateau, 1e-6);
  EXPECT_NEAR(mean_tau_forward(r.dem, 1.0, 2.9), plateau, 0.005 * plateau);
  const auto [dem_f, dem_r] = peaks(r.dem);
  const auto [el_f, el_r] = peaks(r.element);
  EXPECT_NEAR(dem_f, el_f, 0.015 * el_f);
  EXPECT_NEAR(dem_r, el_r, 0.015 * el_r);
  EXPECT_NEAR(normal_disp_at_max_offset(r.dem), normal_disp_at_max_offset(r.element), 0.01);
}

TEST(ElementVsDem, BartonBandisTwoStiffBlocksMatchTheElementDriver) {
  const auto r = run_both("barton_bandis",
                          "kn = \"35.964 GPa/m\"\nks = \"16.929 GPa/m\"\njrc = \"7.1\"\njcs = \"170.5 MPa\"\n"
                          "residual_friction = \"28.4 deg\"\nlab_length = \"0.2032 m\"\n",
                          bb_report());
  const auto [dem_f, dem_r] = peaks(r.dem);
  const auto [el_f, el_r] = peaks(r.element);
  EXPECT_NEAR(dem_f, el_f, 0.015 * el_f);
  EXPECT_NEAR(dem_r, el_r, 0.015 * el_r);
  EXPECT_NEAR(normal_disp_at_max_offset(r.dem), normal_disp_at_max_offset(r.element), 0.01);
}

TEST(ElementVsDem, ContinuouslyYieldingTwoStiffBlocksMatchTheElementDriver) {
  const auto r = run_both("continuously_yielding",
                          "kn = \"29.361 GPa/m\"\nkn_min = \"29.361 GPa/m\"\nkn_max = \"46.109 GPa/m\"\n"
                          "kn_exponent = 0.6783\nks = \"29.312 GPa/m\"\ninitial_friction = \"39.3 deg\"\n"
                          "friction = \"33.5 deg\"\nroughness = \"0.0175 m\"\n",
                          cy_report());
  const auto [dem_f, dem_r] = peaks(r.dem);
  const auto [el_f, el_r] = peaks(r.element);
  EXPECT_NEAR(dem_f, el_f, 0.015 * el_f);
  EXPECT_NEAR(dem_r, el_r, 0.015 * el_r);
  EXPECT_NEAR(normal_disp_at_max_offset(r.dem), normal_disp_at_max_offset(r.element), 0.01);
}
