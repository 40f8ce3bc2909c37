// A laboratory-test case on its DEM specimen (the report's Figure 4-7 model): test 9 with the
// Mohr-Coulomb joint of Table 4-2, first stage (3 MPa, 40 mm forward and back).
// 1. At the report's 100 mm/s and at the laboratory rate (0.042 mm/s, with mass scaling) the
//    records agree: the rate does not matter for a rate-independent joint if the run is
//    quasi-static, which is what the mass scaling must preserve.
// 2. The DEM record against the element test of the same case: close where the specimen is stiff;
//    the difference that remains (block compliance, the non-uniform stress along the joint) is
//    measured and bounded here, and reported in docs/verification.md.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <unistd.h>

#include "framework/analysis/compare.hpp"
#include "framework/simulation/run_case.hpp"
#include "framework/lab/direct_shear_specimen.hpp"
#include "framework/lab/lab_case.hpp"

using namespace rockdem;
namespace fs = std::filesystem;

namespace {

const std::string kCase = std::string(ROCKDEM_SOURCE_DIR) + "/cases/direct_shear/test09_mohr_coulomb.toml";

MeasurementFile run_dem(const LabTest& test, double shear_velocity, double mass_scaling_dt, const std::string& tag) {
  DirectShearOptions o;
  o.shear_velocity = shear_velocity;
  o.mass_scaling_dt = mass_scaling_dt;
  o.stages = 1;
  Case c = direct_shear_case(test, o);
  const fs::path out = fs::temp_directory_path() / ("rockdem_labdem_" + tag + "_" + std::to_string(getpid()));
  RunResult r = run_case(c, out, true);
  fs::remove_all(out);
  return r.lab;
}

// The element record of the first stage only.
MeasurementFile first_stage(MeasurementFile f) {
  std::erase_if(f.rows, [](const MeasurementRow& r) { return r.stage != 1; });
  f.extra.clear();
  f.extra_columns.clear();
  return f;
}

}  // namespace

TEST(LabCaseDem, Test09MohrCoulombStage1LabRateAgreesWithReportRateAndElement) {
  const LabTest test = read_lab_test(kCase);
  const MeasurementFile fast = run_dem(test, 0.1, 0.0, "fast");
  const MeasurementFile lab = run_dem(test, 0.0, 1.2e-3, "lab");
  ASSERT_GT(fast.rows.size(), 1000u);
  ASSERT_GT(lab.rows.size(), 1000u);
  EXPECT_GT(lab.rows.back().time_s, 1800.0);  // 80 mm at 0.042 mm/s
  EXPECT_LT(fast.rows.back().time_s, 1.0);     // at 100 mm/s

  // 1. Rates: aligned on shear displacement, the lab-rate record against the 100 mm/s one.
  const Comparison rates = compare(fast, lab);
  std::printf("lab rate vs 100 mm/s: NRMSE shear stress %.4f, normal displacement %.4f; bias %.4f MPa, %.5f mm\n",
              rates.overall.var[0].nrmse, rates.overall.var[1].nrmse, rates.overall.var[0].bias,
              rates.overall.var[1].bias);
  for (const auto& w : rates.worst) std::printf("  %s\n", w.c_str());
  // Measured: 0.85 % and 0.00 %, the shear-stress part mostly the inertial overshoot of the
  // 100 mm/s run right after the start and the reversal (sub-millimetre); no level shift.
  EXPECT_LT(rates.overall.var[0].nrmse, 0.015);
  EXPECT_LT(std::abs(rates.overall.var[0].bias), 0.01);  // MPa
  EXPECT_LT(rates.overall.var[1].nrmse, 0.02);

  // 2. DEM against the element test of the same case (the element record as "measurement").
  const MeasurementFile element = first_stage(run_element_test(test).record);
  const Comparison dem_vs_element = compare(element, fast);
  std::printf("DEM (100 mm/s) vs element: NRMSE shear stress %.4f, normal displacement %.4f; bias %.4f MPa, %.5f mm\n",
              dem_vs_element.overall.var[0].nrmse, dem_vs_element.overall.var[1].nrmse,
              dem_vs_element.overall.var[0].bias, dem_vs_element.overall.var[1].bias);
  for (const auto& w : dem_vs_element.worst) std::printf("  %s\n", w.c_str());
  // Measured: 1.4 % and 0.2 % (bias 0.002 MPa, -0.003 mm): short transients in the DEM record
  // (start, reversal, a specimen corner passing a gridpoint), no level shift.
  EXPECT_LT(dem_vs_element.overall.var[0].nrmse, 0.025);
  EXPECT_LT(dem_vs_element.overall.var[1].nrmse, 0.04);
}
