// Do calibrate's uncertainties say how far a fitted parameter may be from the truth?
//
// rate_and_state fitted on a velocity-step record once came back with a, b and the critical slip
// 2-5 times off while its standard errors said nothing of it. Here a Mohr-Coulomb joint with
// rate_and_state hidden (the broad blind test's values: a = 0.01, b = 0.03, critical slip
// 100 um) is sheared through five velocity steps (1.5 mm at each of v, 10 v, v/10, 10 v, v at
// 2 MPa), with the blind tests' noise (0.005 MPa, 0.002 mm), and calibrated with every parameter
// profiled (calibration_profile.cpp), three seeds. Measured 2026-11-29: the fits land within 13 %
// of the truth, and the profile-likelihood 95 % intervals hold it in 6 of 9 (the linearised ones,
// value +- 1.96 s.e., in 5): the fits carry a bias beyond the noise (seeds 2 and 3: a and b low
// by 1.0-1.4 interval half-widths) that neither interval can know of (docs/validation.md).
// What is asserted:
//  - on this nearly linear problem, no parameter near a bound, the profile interval is as wide
//    as the linearised one (within a factor 0.7-1.4; measured 0.96-1.03);
//  - the truth lies within twice the interval's half-width of the fitted value: an answer 2-5
//    times off with an interval that does not say so fails.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "tests/unit/noisy_record.hpp"
#include "framework/analysis/calibration.hpp"
#include "framework/lab/element_driver.hpp"
#include "framework/plugin_api/joint_law.hpp"

using namespace rockdem;

namespace {

RawValue q(const char* text) { return RawValue{std::string(text), "test"}; }

constexpr double kStep = 2.5e-5;  // element increment [m]
constexpr double kV = 4.2e-5;     // the report's pseudostatic rate [m/s]

MeasurementFile velocity_steps(const JointModel& model, unsigned seed) {
  ElementOptions eo;
  eo.max_step = kStep;
  eo.output_every = 4;
  eo.length = 0.2;
  std::vector<double> t{0.0}, u{0.0};
  for (double v : {kV, 10 * kV, kV / 10, 10 * kV, kV}) {
    t.push_back(t.back() + 1.5e-3 / v);
    u.push_back(u.back() + 1.5e-3);
  }
  std::vector<ElementStage> stages(1);
  stages[0].normal_stress = 2e6;
  stages[0].path = ShearPath::table(t, u);
  ElementDriver d(model, eo);
  MeasurementFile f = d.run(stages);
  testutil::add_noise(f, seed);
  f.metadata.push_back({"joint_length_m", "0.2"});
  return f;
}

}  // namespace

TEST(ProfileCoverage, RateAndStateIntervalsSayHowFarTheTruthMayBe) {
  const RawValues law{{"kn", q("40 GPa/m")},         {"ks", q("12 GPa/m")},
                      {"friction", q("36 deg")},     {"dilation_angle", q("8 deg")},
                      {"dilation", q("reversible")}};
  const RawValues rs{{"a", q("0.01")}, {"b", q("0.03")}, {"critical_slip", q("100 um")}};
  const std::vector<std::pair<std::string, double>> truth{
      {"rate_and_state.a", 0.01}, {"rate_and_state.b", 0.03}, {"rate_and_state.critical_slip", 100e-6}};
  auto model = make_joint_model("mohr_coulomb", law, {EffectSpec{"rate_and_state", rs, "test"}}, "test");
  int held = 0, tried = 0, linear_held = 0;
  for (const unsigned seed : {1u, 2u, 3u}) {
    const MeasurementFile f = velocity_steps(*model, seed);
    CalibrationOptions o;
    o.law = "mohr_coulomb";
    o.law_values["dilation"] = q("reversible");
    o.law_values["kn"] = q("40 GPa/m");
    o.effects = {"rate_and_state"};
    o.element.max_step = kStep;
    o.element.length = 0.2;
    o.fit_step = kStep;
    o.profile = CalibrationOptions::Profile::all;
    const CalibrationResult r = calibrate(f, segment(f), o);
    for (const auto& [name, value] : truth) {
      for (const auto& p : r.params) {
        if (p.name != name) continue;
        ASSERT_TRUE(p.profiled()) << name;
        const bool in = p.profile_lower <= value && value <= p.profile_upper;
        const bool linear_in = std::abs(p.value - value) <= 1.96 * p.se;
        std::printf("seed %u %-30s true %-9.4g fitted %-9.4g +- %-9.3g profile %s%.4g .. %.4g%s%s\n", seed, name.c_str(), value,
                    p.value, 1.96 * p.se, p.profile_lower_open ? "(bound) " : "", p.profile_lower, p.profile_upper,
                    p.profile_upper_open ? " (bound)" : "", in ? "" : "  MISSES THE TRUTH");
        ++tried;
        held += in ? 1 : 0;
        linear_held += linear_in ? 1 : 0;
        const double half = 0.5 * (p.profile_upper - p.profile_lower);
        EXPECT_LE(std::abs(p.value - value), 2.0 * half)
            << "seed " << seed << ": " << name << " true " << value << ", fitted " << p.value << ", interval " << p.profile_lower
            << " .. " << p.profile_upper;
        const double ratio = (p.profile_upper - p.profile_lower) / (2.0 * 1.96 * p.se);
        EXPECT_GT(ratio, 0.7) << "seed " << seed << ": " << name;
        EXPECT_LT(ratio, 1.4) << "seed " << seed << ": " << name;
      }
    }
  }
  std::printf("profile intervals hold the truth %d of %d; linearised intervals %d of %d\n", held, tried, linear_held, tried);
  EXPECT_EQ(tried, 9);
}
