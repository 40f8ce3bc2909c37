#pragma once
// A synthetic measurement for the calibration, diagnosis and blind tests: a joint model through
// two stages (2 and 4 MPa) of 10 mm strokes at 0.042 mm/s (one-sided 0 -> +10 mm -> 0, or full
// cycles 0 -> +10 -> 0 -> -10 -> 0), every `output_every`-th increment of `max_step` kept, with
// seeded Gaussian noise of noise_scale x (5 kPa shear stress, 2 um normal displacement).
#include <random>
#include <vector>

#include "framework/io/measurement_csv.hpp"
#include "framework/lab/element_driver.hpp"
#include "framework/plugin_api/joint_law.hpp"

namespace rockdem::testutil {

// Tuff-like joints of the diagnosis tests (clean controls, the broad blind test): Barton-Bandis with
// reversible dilation and Continuously-Yielding with monotonic dilation.
inline RawValues barton_bandis_joint() {
  auto q = [](const char* text) { return RawValue{std::string(text), "test"}; };
  return {{"kn", q("40 GPa/m")}, {"ks", q("12 GPa/m")},         {"jrc", q("8")},
          {"jcs", q("120 MPa")}, {"residual_friction", q("30 deg")}, {"lab_length", q("0.2 m")},
          {"dilation", q("reversible")}};
}
inline RawValues continuously_yielding_joint() {
  auto q = [](const char* text) { return RawValue{std::string(text), "test"}; };
  return {{"kn", q("40 GPa/m")},      {"ks", q("15 GPa/m")},   {"initial_friction", q("50 deg")},
          {"friction", q("32 deg")}, {"roughness", q("3 mm")}, {"dilation", q("monotonic")}};
}

// Slides of `slide` [m] at `v` [m/s] in one direction, separated by holds of `holds_s` (in that
// order): a slide-hold-slide test's shear path.
inline ShearPath slide_hold_slide_path(double v, double slide, const std::vector<double>& holds_s) {
  std::vector<double> t{0.0}, u{0.0};
  for (std::size_t k = 0; k <= holds_s.size(); ++k) {
    t.push_back(t.back() + slide / v);
    u.push_back(u.back() + slide);
    if (k < holds_s.size()) {
      t.push_back(t.back() + holds_s[k]);
      u.push_back(u.back());
    }
  }
  return ShearPath::table(t, u);
}

// The tests' white noise: 0.005 MPa on the shear stress, 0.002 mm on the normal displacement
// (times `scale`), from `seed`.
inline void add_noise(MeasurementFile& f, unsigned seed, double scale = 1.0) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  for (auto& r : f.rows) {
    r.shear_stress_MPa += scale * 0.005 * g(rng);
    r.normal_disp_mm += scale * 0.002 * g(rng);
  }
}

inline MeasurementFile noisy_two_stage_record(const JointModel& model, double max_step, int output_every, bool one_sided,
                                              unsigned seed, double noise_scale = 1.0) {
  ElementOptions eo;
  eo.max_step = max_step;
  eo.output_every = output_every;
  eo.length = 0.2;
  ElementDriver d(model, eo);
  std::vector<ElementStage> stages(2);
  for (std::size_t i = 0; i < stages.size(); ++i) {
    stages[i].normal_stress = 2e6 * static_cast<double>(i + 1);
    stages[i].path = ShearPath::cycles(0.01, 1, 4.2e-5, one_sided);
  }
  MeasurementFile f = d.run(stages);
  add_noise(f, seed, noise_scale);
  f.metadata.push_back({"joint_length_m", "0.2"});
  return f;
}

}  // namespace rockdem::testutil
