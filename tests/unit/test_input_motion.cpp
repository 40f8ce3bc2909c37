// Seismic input processing (framework/seismic/input_motion.hpp, peer_at2.cpp) and the case
// keys that use it ([[motions]], stage motion keys, seismic and free_field boundaries, Rayleigh
// damping over a band): each step against a closed form, and the mistakes a user makes.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>
#include <unistd.h>

#include "framework/core/error.hpp"
#include "framework/io/case.hpp"
#include "framework/mechanics/engine_settings.hpp"
#include "framework/seismic/input_motion.hpp"

using namespace rockdem;
using namespace rockdem::seismic;
namespace fs = std::filesystem;

namespace {

GroundMotion sine_record(double f, double amplitude, double dt, double duration) {
  GroundMotion g;
  g.source = "sine";
  g.column_name = "acc";
  g.dt = dt;
  for (double t = 0.0; t <= duration + 1e-12; t += dt) g.acc.push_back(amplitude * std::sin(2.0 * std::numbers::pi * f * t));
  return g;
}

fs::path temp_file(const std::string& name, const std::string& text) {
  const fs::path p = fs::temp_directory_path() / ("rockdem_test_motion_" + std::to_string(::getpid()) + "_" + name);
  std::ofstream(p) << text;
  return p;
}

}  // namespace

TEST(InputMotion, ScalesToTargetPeaksAndEndsAtRest) {
  const GroundMotion g = sine_record(2.0, 1.0, 0.005, 3.1);  // 6.2 cycles: integration leaves a velocity
  DisplacementProcessing p;
  p.acc_baseline_degree = -1;
  const InputMotion m = make_input_motion(g, p, {MotionScaling::Kind::pga, 0.3 * 9.81});
  EXPECT_NEAR(m.pga(), 0.3 * 9.81, 1e-12);
  EXPECT_NEAR(m.vel.back(), 0.0, 1e-15) << "the motion ends at rest";
  // Velocity is the running integral of the acceleration (trapezoid rule), after the correction.
  double v = 0.0;
  for (std::size_t i = 1; i < m.acc.size(); ++i) v += 0.5 * (m.acc[i - 1] + m.acc[i]) * m.dt;
  EXPECT_NEAR(v, m.vel.back(), 1e-12);
  const InputMotion n = make_input_motion(g, p, {MotionScaling::Kind::pgv, 0.2});
  EXPECT_NEAR(n.pgv(), 0.2, 1e-12);
  const InputMotion k = make_input_motion(g, p, {MotionScaling::Kind::factor, 2.0});
  EXPECT_NEAR(k.pga(), 2.0 * make_input_motion(g, p, {}).pga(), 1e-12);
  // Between samples linear, zero outside the motion.
  EXPECT_DOUBLE_EQ(m.velocity(0.5 * (m.dt * 10 + m.dt * 11)), 0.5 * (m.vel[10] + m.vel[11]));
  EXPECT_EQ(m.velocity(-0.1), 0.0);
  EXPECT_EQ(m.velocity(m.duration() + 0.1), 0.0);
  EXPECT_EQ(m.displacement(m.duration() + 0.1), m.disp.back());
}

TEST(InputMotion, MeshLimitAndPowerFrequency) {
  // Kuhlemeyer & Lysmer: 10 zones per wavelength of 500 m/s shear waves in 1 m zones: 50 Hz.
  EXPECT_DOUBLE_EQ(mesh_frequency_limit(500.0, 1.0, 10.0), 50.0);
  // A pure 5 Hz sine over whole cycles has all its power at 5 Hz.
  const GroundMotion g = sine_record(5.0, 1.0, 0.001, 2.0 - 0.001);
  EXPECT_NEAR(power_frequency(g.acc, g.dt, 0.99), 5.0, 0.51);
}

TEST(InputMotion, ReadsPeerAt2InBothHeaderForms) {
  const std::string values = "  .1000000E-01  .2000000E-01 -.3000000E-01\n  .4000000E-01  .5000000E-01\n";
  const fs::path a = temp_file("new.AT2", "PEER NGA STRONG MOTION DATABASE RECORD\nTest, 1/1/2000, Station, 90\n"
                                          "ACCELERATION TIME SERIES IN UNITS OF G\nNPTS=    5, DT=   .0100 SEC\n" + values);
  const GroundMotion g = load_peer_at2(a.string());
  ASSERT_EQ(g.acc.size(), 5u);
  EXPECT_DOUBLE_EQ(g.dt, 0.01);
  EXPECT_DOUBLE_EQ(g.acc[2], -0.03 * 9.80665);
  const fs::path b = temp_file("old.at2", "PEER STRONG MOTION DATABASE RECORD\nTest\nACCELERATION TIME HISTORY IN UNITS OF G\n"
                                          "    5    0.0100    NPTS, DT\n" + values);
  EXPECT_EQ(load_peer_at2(b.string()).acc, g.acc);
  // Fewer values than NPTS, a bad number, no unit: each names the file and line.
  const fs::path c = temp_file("short.AT2", "x\nx\nACCELERATION IN UNITS OF G\nNPTS=    6, DT=   .0100 SEC\n" + values);
  EXPECT_THROW(load_peer_at2(c.string()), InputError);
  const fs::path d = temp_file("bad.AT2", "x\nx\nUNITS OF G\nNPTS=    2, DT=   .0100 SEC\n 0.1 abc\n");
  try {
    load_peer_at2(d.string());
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(d.string() + ":5"), std::string::npos) << e.what();
  }
  const fs::path e = temp_file("unit.AT2", "x\nx\nACCELERATION\nNPTS=    2, DT=   .0100 SEC\n 0.1 0.2\n");
  EXPECT_THROW(load_peer_at2(e.string()), InputError);
  for (const auto& p : {a, b, c, d, e}) fs::remove(p);
}

TEST(InputMotion, RayleighBandGivesTheFractionAtBothEnds) {
  const Damping d = Damping::rayleigh_band(0.05, 1.0, 10.0);
  auto xi = [&](double f) {
    const double w = 2.0 * std::numbers::pi * f;
    return 0.5 * (d.alpha / w + d.beta * w);
  };
  EXPECT_NEAR(xi(1.0), 0.05, 1e-14);
  EXPECT_NEAR(xi(10.0), 0.05, 1e-14);
  EXPECT_LT(xi(3.0), 0.05);
}

namespace {

// A column case with a [[motions]] entry and a seismic base; `motion_extra` goes into
// [[motions]], `stage_extra` into the shaking stage, `base_extra` into the seismic boundary.
std::string motion_case(const std::string& motion_extra, const std::string& stage_extra = "",
                        const std::string& base_extra = "", const std::string& zones = "[1, 50]") {
  return R"([[materials]]
name = "rock"
model = "elastic"
density = "2000 kg/m3"
bulk = "1.3333333333 GPa"
shear = "0.5 GPa"
[[blocks]]
name = "column"
type = "deformable"
material = "rock"
rectangle = ["0 m", "0 m", "1 m", "50 m"]
zones = )" + zones + R"(
[[motions]]
name = "eq"
file = ")" + (fs::path(ROCKDEM_SOURCE_DIR) / "cases/data/ground_motions/elcentro1940_ns_acc_g.csv").string() + R"("
)" + motion_extra + R"(
[[boundary]]
type = "seismic"
block = "column"
face = "bottom"
)" + base_extra + R"(
[[stages]]
name = "shake"
damping = "none"
motion = "eq"
duration = "auto"
)" + stage_extra + "\n";
}

std::string error_of(const std::string& text) {
  try {
    load_case_text(text, "motion.toml", ".");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(InputMotion, CaseKeysAndTheirMistakes) {
  EXPECT_EQ(error_of(motion_case("")), "");
  // A scale per stage multiplies the motion; a target peak scales the first motion to it.
  {
    const Case c = load_case_text(motion_case("", "pga = \"0.2 g\""), "m.toml", ".");
    const auto& st = c.stages.front();
    ASSERT_EQ(st.motions.size(), 1u);
    EXPECT_NEAR(st.motions[0].factor * c.motions[0]->pga(), 0.2 * 9.80665, 1e-9);
  }
  auto has = [](const std::string& msg, const std::string& part) {
    return msg.find(part) != std::string::npos;
  };
  EXPECT_TRUE(has(error_of(motion_case("type = \"surface\"")), "motion.toml:16 key 'motions.type': unknown type 'surface'"));
  EXPECT_TRUE(has(error_of(motion_case("pga = \"0.3 g\"\npgv = \"1 m/s\"")), "give one of scale, pga and pgv"));
  EXPECT_TRUE(has(error_of(motion_case("", "motion_scale = 2\npga = \"1 g\"")), "give one of motion_scale, pga and pgv"));
  EXPECT_TRUE(has(error_of(motion_case("type = \"within\"")), "is a within record"));
  EXPECT_EQ(error_of(motion_case("type = \"within\"", "", "base = \"rigid\"")), "");
  EXPECT_TRUE(has(error_of(motion_case("", "", "base = \"stiff\"")), "unknown base 'stiff'; valid: compliant"));
  EXPECT_TRUE(has(error_of(motion_case("window = [\"5 s\", \"2 s\"]")), "needs 0 <= start < end"));
  EXPECT_TRUE(has(error_of(motion_case("unit = \"furlong\"")), "key 'motions.unit'"));
  // A record above what the zones carry: refused with the limit, or low-passed at it.
  // 1 x 10 m zones (two triangles each, longest edge sqrt(101) m) carry 10 zones per 500 m/s
  // wavelength up to 500 / (10 sqrt(101)) = 4.975 Hz.
  const std::string refused = error_of(motion_case("above_mesh = \"refuse\"\nfilter = { high = \"20 Hz\" }", "", "", "[1, 5]"));
  EXPECT_TRUE(has(refused, "carries frequencies up to 20 Hz (filter.high), above what the mesh carries")) << refused;
  EXPECT_TRUE(has(refused, "up to 4.975 Hz")) << refused;
  {
    const Case c = load_case_text(motion_case("", "", "", "[1, 5]"), "m.toml", ".");
    EXPECT_NEAR(c.motions[0]->f_high, 500.0 / (10.0 * std::sqrt(101.0)), 1e-9);
    EXPECT_TRUE(has(c.motions[0]->processing, "low-pass at 4.975 Hz by the mesh")) << c.motions[0]->processing;
  }
  // A stage that plays a motion needs a boundary that takes it; stage names a motion that exists.
  std::string no_base = motion_case("");
  no_base.replace(no_base.find("type = \"seismic\""), 16, "type = \"quiet\"");
  EXPECT_TRUE(has(error_of(no_base), "no boundary takes it"));
  std::string unknown = motion_case("");
  unknown.replace(unknown.find("motion = \"eq\""), 13, "motion = \"eq2\"");
  EXPECT_TRUE(has(error_of(unknown), "no motion named 'eq2'; motions: eq"));
  std::string empty = motion_case("");
  empty.replace(empty.find("motion = \"eq\""), 13, "motion = []");
  EXPECT_TRUE(has(error_of(empty), "name at least one"));
  // Rigid blocks need the rock's wave speeds for dashpots.
  std::string rigid = motion_case("");
  rigid.replace(rigid.find("type = \"deformable\""), 19, "type = \"rigid\"\ndensity = \"2000 kg/m3\"");
  EXPECT_TRUE(has(error_of(rigid), "give the rock's cp and cs"));
  // Damping over a band.
  auto band = [&](const std::string& freqs) {
    std::string t = motion_case("");
    t.replace(t.find("damping = \"none\""), 16, "damping = \"rayleigh\"\ndamping_ratio = 0.05\ndamping_frequency = " + freqs);
    return t;
  };
  EXPECT_TRUE(has(error_of(band("[\"10 Hz\", \"1 Hz\"]")), "needs 0 < f1 < f2"));
  {
    const Case c = load_case_text(band("[\"1 Hz\", \"10 Hz\"]"), "m.toml", ".");
    const Damping d = Damping::rayleigh_band(0.05, 1.0, 10.0);
    EXPECT_DOUBLE_EQ(c.stages[0].damping.alpha, d.alpha);
    EXPECT_DOUBLE_EQ(c.stages[0].damping.beta, d.beta);
  }
}
