// The 21 laboratory-test cases (tests 7-11, 14, 24 x three laws, written by scripts/make-lab-cases)
// against the report's tables they come from (cases/direct_shear/data/lab_tables): every parameter
// of Tables 4-1..4-4 reaches the case with its unit, each test has the stages the report describes,
// and every case runs as an element test through its whole path.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "framework/core/params.hpp"
#include "framework/lab/direct_shear_specimen.hpp"
#include "framework/lab/lab_case.hpp"

using namespace rockdem;

namespace {

const std::string kDir = std::string(ROCKDEM_SOURCE_DIR) + "/cases/direct_shear/";

// Rows of a table CSV ('#' lines skipped) as column -> text.
std::vector<std::map<std::string, std::string>> table(const std::string& name) {
  std::ifstream in(kDir + "data/lab_tables/" + name);
  std::vector<std::string> header;
  std::vector<std::map<std::string, std::string>> rows;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::vector<std::string> f;
    std::stringstream ss(line);
    for (std::string x; std::getline(ss, x, ',');) f.push_back(x);
    if (header.empty()) {
      header = f;
      continue;
    }
    std::map<std::string, std::string> r;
    for (std::size_t i = 0; i < header.size() && i < f.size(); ++i) r[header[i]] = f[i];
    rows.push_back(r);
  }
  return rows;
}

double num(const std::map<std::string, std::string>& r, const std::string& k) { return std::stod(r.at(k)); }

// A parameter of the case's [joint.params] (or a stage's overrides), in SI units.
double param(const toml::table& t, const std::string& key, Dimension d) {
  const auto* n = t.get(key);
  if (!n) ADD_FAILURE() << "missing parameter " << key;
  if (!n) return NAN;
  RawValue raw;
  if (const auto* s = n->as_string()) raw.value = s->get();
  else if (const auto* f = n->as_floating_point()) raw.value = f->get();
  else if (const auto* i = n->as_integer()) raw.value = static_cast<double>(i->get());
  raw.where = key;
  return quantity_value(raw, d, key);
}

std::string case_path(int test, const std::string& law) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "test%02d_%s.toml", test, law.c_str());
  return kDir + buf;
}

void expect_rel(double got, double want, const std::string& what) {
  EXPECT_NEAR(got, want, 1e-9 * std::abs(want) + 1e-12) << what;
}

}  // namespace

TEST(LabCases, MohrCoulombCasesCarryTable42StageByStage) {
  std::map<int, std::vector<std::map<std::string, std::string>>> by_test;
  for (const auto& r : table("mohr_coulomb.csv")) by_test[std::stoi(r.at("test_no"))].push_back(r);
  ASSERT_EQ(by_test.size(), 7u);
  for (const auto& [test, rows] : by_test) {
    const LabTest c = read_lab_test(case_path(test, "mohr_coulomb"));
    ASSERT_EQ(c.stages.size(), rows.size()) << "test " << test;
    for (std::size_t k = 0; k < rows.size(); ++k) {
      const auto& r = rows[k];
      const std::string what = "test " + std::to_string(test) + " stage " + std::to_string(k + 1);
      expect_rel(c.stages[k].normal_stress, num(r, "normal_stress_MPa") * 1e6, what + " normal stress");
      // Stage k's values: [joint.params] overridden by the stage's [stage.params].
      toml::table p = c.joint_params;
      for (const auto& [key, v] : c.stage_params[k]) p.insert_or_assign(key, v);
      expect_rel(param(p, "kn", Dimension::stiffness), num(r, "jkn_MPa_per_m") * 1e6, what + " kn");
      expect_rel(param(p, "ks", Dimension::stiffness), num(r, "jks_MPa_per_m") * 1e6, what + " ks");
      expect_rel(param(p, "friction", Dimension::angle), num(r, "jfric_deg") * M_PI / 180, what + " friction");
      expect_rel(param(p, "cohesion", Dimension::stress), num(r, "jcoh_MPa") * 1e6, what + " cohesion");
      expect_rel(param(p, "dilation_angle", Dimension::angle), num(r, "jdil_deg") * M_PI / 180, what + " dilation");
      expect_rel(param(p, "critical_shear_disp", Dimension::length), num(r, "z_dilation_m"), what + " u_cs");
      if (k > 0) {
        EXPECT_TRUE(c.stages[k].model) << what << ": a later stage needs its own parameter values";
      }
    }
  }
}

TEST(LabCases, BartonBandisAndContinuouslyYieldingCasesCarryTables43And44) {
  for (const auto& r : table("barton_bandis.csv")) {
    const int test = std::stoi(r.at("test_no"));
    const LabTest c = read_lab_test(case_path(test, "barton_bandis"));
    const std::string what = "BB test " + std::to_string(test);
    expect_rel(param(c.joint_params, "kn", Dimension::stiffness), num(r, "jkn_MPa_per_m") * 1e6, what + " kn");
    expect_rel(param(c.joint_params, "ks", Dimension::stiffness), num(r, "jks_MPa_per_m") * 1e6, what + " ks");
    expect_rel(param(c.joint_params, "jcs", Dimension::stress), num(r, "jcs0_MPa") * 1e6, what + " jcs");
    expect_rel(param(c.joint_params, "ucs", Dimension::stress), num(r, "sigmac_MPa") * 1e6, what + " ucs");
    expect_rel(param(c.joint_params, "jrc", Dimension::dimensionless), num(r, "jrco"), what + " jrc");
    expect_rel(param(c.joint_params, "residual_friction", Dimension::angle), num(r, "phir_deg") * M_PI / 180, what + " phir");
    expect_rel(param(c.joint_params, "lab_length", Dimension::length), num(r, "lo_m"), what + " lo");
    expect_rel(param(c.joint_params, "field_length", Dimension::length), num(r, "ln_m"), what + " ln");
  }
  for (const auto& r : table("continuously_yielding.csv")) {
    const int test = std::stoi(r.at("test_no"));
    const LabTest c = read_lab_test(case_path(test, "continuously_yielding"));
    const std::string what = "CY test " + std::to_string(test);
    const auto& p = c.joint_params;
    expect_rel(param(p, "kn", Dimension::stiffness), num(r, "jkn_MPa_per_m") * 1e6, what + " kn");
    expect_rel(param(p, "kn_min", Dimension::stiffness), num(r, "minjkn_MPa_per_m") * 1e6, what + " kn_min");
    expect_rel(param(p, "kn_max", Dimension::stiffness), num(r, "maxjkn_MPa_per_m") * 1e6, what + " kn_max");
    expect_rel(param(p, "kn_exponent", Dimension::dimensionless), num(r, "jen"), what + " jen");
    expect_rel(param(p, "ks", Dimension::stiffness), num(r, "jks_MPa_per_m") * 1e6, what + " ks");
    expect_rel(param(p, "ks_min", Dimension::stiffness), num(r, "minjks_MPa_per_m") * 1e6, what + " ks_min");
    expect_rel(param(p, "ks_max", Dimension::stiffness), num(r, "maxjks_MPa_per_m") * 1e6, what + " ks_max");
    expect_rel(param(p, "initial_friction", Dimension::angle), num(r, "jif_deg") * M_PI / 180, what + " jif");
    expect_rel(param(p, "friction", Dimension::angle), num(r, "jfric_deg") * M_PI / 180, what + " jfric");
    expect_rel(param(p, "roughness", Dimension::length), num(r, "jr_m"), what + " jr");
  }
}

TEST(LabCases, RockMatrixFromTable41ReachesTheDemSpecimen) {
  for (const auto& r : table("rock_matrix.csv")) {
    const int test = std::stoi(r.at("test_no"));
    for (const std::string law : {"mohr_coulomb", "barton_bandis", "continuously_yielding"}) {
      const LabTest c = read_lab_test(case_path(test, law));
      ASSERT_TRUE(c.rock.has_value());
      expect_rel(c.rock->density, num(r, "density_kg_m3"), "density");
      expect_rel(c.rock->bulk, num(r, "bulk_modulus_GPa") * 1e9, "bulk");
      expect_rel(c.rock->shear, num(r, "shear_modulus_GPa") * 1e9, "shear");
      // The DEM case builds and checks (geometry, boundaries, stages) without running.
      const Case dem = direct_shear_case(c);
      EXPECT_EQ(dem.direct_shear.shear_stages.size(), c.stages.size());
      EXPECT_EQ(dem.stages.size(), 2 * c.stages.size());
    }
  }
}

// Every case runs as an element test and follows the report's paths: tests 7-11 go 40 mm forward
// and back in every stage, test 14 is a 12.7 mm sinusoid over 40 cycles, test 24 peaks at 25.4 mm.
TEST(LabCases, EveryCaseRunsAsAnElementTestThroughItsPath) {
  for (int test : {7, 8, 9, 10, 11, 14, 24}) {
    for (const std::string law : {"mohr_coulomb", "barton_bandis", "continuously_yielding"}) {
      const LabTest c = read_lab_test(case_path(test, law));
      const ElementRun run = run_element_test(c);
      EXPECT_EQ(run.unconverged, 0) << test << " " << law;
      std::map<int, std::pair<double, double>> range;  // stage -> (min, max) shear displacement
      double peak_tau = 0.0;
      for (const auto& row : run.record.rows) {
        auto& [lo, hi] = range.try_emplace(row.stage, 1e9, -1e9).first->second;
        lo = std::min(lo, row.shear_disp_mm);
        hi = std::max(hi, row.shear_disp_mm);
        peak_tau = std::max(peak_tau, std::abs(row.shear_stress_MPa / row.normal_stress_MPa));
        ASSERT_TRUE(std::isfinite(row.shear_stress_MPa) && std::isfinite(row.normal_disp_mm));
      }
      ASSERT_EQ(range.size(), c.stages.size());
      for (const auto& [stage, r] : range) {
        if (test <= 11) {
          EXPECT_NEAR(r.second, 40.0, 1e-9) << test << " " << law << " stage " << stage;
          EXPECT_NEAR(r.first, 0.0, 1e-9);
          EXPECT_NEAR(run.record.rows.back().shear_disp_mm, 0.0, 1e-9);
        } else if (test == 14) {
          EXPECT_NEAR(r.second, 12.7, 1e-3);
          EXPECT_NEAR(r.first, -12.7, 1e-3);
        } else {
          EXPECT_NEAR(std::max(r.second, -r.first), 25.4, 0.03);
        }
      }
      // Friction angles of 25-58 degrees: tau/sigma_n between tan 20 and tan 70 at its peak.
      EXPECT_GT(peak_tau, std::tan(20 * M_PI / 180)) << test << " " << law;
      EXPECT_LT(peak_tau, std::tan(70 * M_PI / 180)) << test << " " << law;
    }
  }
}
