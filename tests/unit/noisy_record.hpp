#pragma once
// A synthetic measurement for the calibration, diagnosis and blind tests: a joint model through
// two stages (2 and 4 MPa) of 10 mm strokes at 0.042 mm/s (one-sided 0 -> +10 mm -> 0, or full
// cycles 0 -> +10 -> 0 -> -10 -> 0), every `output_every`-th increment of `max_step` kept, with
// seeded Gaussian noise of noise_scale x (5 kPa shear stress, 2 um normal displacement).
#include <random>
#include <vector>

#include "framework/io/measurement_csv.hpp"
#include "framework/lab/element_driver.hpp"

namespace rockdem::testutil {

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
  std::mt19937 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  for (auto& r : f.rows) {
    r.shear_stress_MPa += noise_scale * 0.005 * g(rng);
    r.normal_disp_mm += noise_scale * 0.002 * g(rng);
  }
  f.metadata.push_back({"joint_length_m", "0.2"});
  return f;
}

}  // namespace rockdem::testutil
