// dilation_recovery represents the recovery shapes of the CNWRA report (Figures 2-2, 2-7, 2-8;
// issue 15: "curved or straight, to zero or to a residual"), fitted to records it did not make.
// The record: Mohr-Coulomb (dilation "monotonic", 5 deg) whose dilation falls back along a
// straight line to a residual rho of the dilation at the reversal, made by a test-only plug-in
// that gives dilation back at the rate aiming at the residual at the origin
// (tests/plugins/constant_rate_recovery_effect.cpp: other code than the catalogue's target path),
// two stages (2 and 4 MPa) of 0 -> 10 mm -> 0, seeded noise. Calibrating Mohr-Coulomb +
// dilation_recovery must find a straight path (hysteresis below 0.1) and the record's residual
// (within 0.02 of the noise-free record's dilation at the origin over that at the reversal), and
// its combined NRMSE must be within 5 times the ceiling (the noisy record against the noise-free
// one). Not at the ceiling: the record's line starts where the joint starts sliding back, about
// 0.5 mm after the reversal (the elastic part gives nothing back), the effect's at the reversal,
// whose lag it catches up at twice the slope; that corner is the rest of the error (measured
// 2026-11-29: 0.0058 and 0.0046 against a ceiling of 0.0016, residual 0.202 and 0.502, hysteresis
// 0). With the path before 2026-11-29, max(rho d_r, d_r g(x)), the recovery stopped at the
// residual short of the origin: residual_fraction 0.004 and 0.697, combined NRMSE 0.030 and 0.049.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "tests/unit/noisy_record.hpp"
#include "framework/analysis/calibration.hpp"
#include "framework/analysis/compare.hpp"
#include "framework/analysis/segmentation.hpp"
#include "framework/plugin_api/joint_law.hpp"

using namespace rockdem;

namespace {

RawValue q(const std::string& t) { return RawValue{t, "test"}; }

const RawValues kLaw{{"kn", q("40 GPa/m")},
                     {"ks", q("12 GPa/m")},
                     {"friction", q("36 deg")},
                     {"dilation_angle", q("5 deg")},
                     {"dilation", q("monotonic")}};

MeasurementFile straight_return(double rho, unsigned seed, double noise) {
  auto model = make_joint_model("mohr_coulomb", kLaw,
                                {EffectSpec{"constant_rate_recovery", {{"residual", q(std::to_string(rho))}}, "test"}}, "test");
  return testutil::noisy_two_stage_record(*model, 2.5e-5, 4, true, seed, noise);
}

// The dilation left at the end of each stage over the largest of that stage (noise-free record:
// the normal displacement under constant normal stress is the dilation plus a constant closure).
double record_residual(const MeasurementFile& f) {
  double d_max = -1e300, d_end = 0.0, d_start = f.rows.front().normal_disp_mm;
  for (const auto& r : f.rows) {
    if (r.stage != f.rows.front().stage) break;
    d_max = std::max(d_max, r.normal_disp_mm - d_start);
    d_end = r.normal_disp_mm - d_start;
  }
  return d_end / d_max;
}

}  // namespace

TEST(DilationRecoveryShapes, AStraightReturnToAResidualIsMetAtTheNoise) {
  ASSERT_NE(EffectRegistry::instance().find("constant_rate_recovery"), nullptr) << "the test plug-in is not linked in";
  for (const double rho : {0.2, 0.5}) {
    const MeasurementFile clean = straight_return(rho, 1, 0.0);
    const MeasurementFile noisy = straight_return(rho, 7, 1.0);
    const double ceiling = compare(noisy, clean).combined_nrmse;
    const double rho_record = record_residual(clean);

    CalibrationOptions o;
    o.law = "mohr_coulomb";
    o.law_values["dilation"] = q("monotonic");
    o.effects = {"dilation_recovery"};
    o.element.max_step = 2.5e-5;
    o.element.length = 0.2;
    o.fit_step = 5e-5;
    const CalibrationResult r = calibrate(noisy, segment(noisy), o);
    const double h = r.value("dilation_recovery.hysteresis"), rho_fit = r.value("dilation_recovery.residual_fraction");
    std::printf("  rho %.2f (record %.3f): fitted residual_fraction %.3f, hysteresis %.3f, combined NRMSE %.4f (%.4f, %.4f), ceiling %.4f\n",
                rho, rho_record, rho_fit, h, r.nrmse[2], r.nrmse[0], r.nrmse[1], ceiling);
    EXPECT_LE(r.nrmse[2], 5.0 * ceiling) << "rho " << rho;
    EXPECT_LT(h, 0.1) << "a straight return (rho " << rho << ")";
    EXPECT_NEAR(rho_fit, rho_record, 0.02) << "rho " << rho;
  }
}
