#pragma once
// A measurement twin: a virtual-lab case file (cases/virtual_lab/testNN.toml) read into the
// specimen's profile, contact and noise parameters and its stages, and run on a ShearBox into a
// record in the measurement format labelled `source: synthetic`. Keys:
//   [virtual_lab]   specimen (text) and the parameters of TwinSettings::spec() (with units)
//   [[stage]]       the laboratory-test stage keys (framework/lab/lab_case.hpp read_stage)
// Every mistake is an InputError naming file:line and key, what is wrong and what is valid.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "framework/core/params.hpp"
#include "framework/io/measurement_csv.hpp"
#include "framework/lab/element_driver.hpp"
#include "framework/lab/virtual_lab/shear_box.hpp"

namespace rockdem::vlab {

struct TwinSettings {
  int seed;
  double top_length, bottom_length, grid;
  double jrc, hurst, min_wavelength, max_wavelength, mismatch_wavelength;
  double friction, contact_stiffness, shear_stiffness, wall_strength, wear_coefficient, max_angle;
  int dynamics;  // 0 quasi_static, 1 inertial
  double frame_stiffness, density, moving_height, time_step;
  bool rate_state;
  double rs_a, rs_b, rs_dc, rs_v0;
  double step, output_interval;
  double noise_stress, noise_shear_disp, noise_normal_disp;
  static std::vector<Param<TwinSettings>> spec();
};

struct TwinCase {
  std::string file;
  std::string specimen;
  TwinSettings settings{};
  std::vector<ElementStage> stages;
};

TwinCase read_twin_case(const std::string& file);

// The profile spec and box parameters a twin's settings describe.
ProfileSpec profile_spec(const TwinSettings& s, std::uint64_t seed);
BoxParams box_params(const TwinSettings& s);

struct TwinRun {
  MeasurementFile record;
  std::uint64_t seed = 0;
  double profile_jrc = 0.0;  // JRC of the generated profile by Tse & Cruden (equals the target)
  long steps = 0;
  double wall_ms = 0.0;
};

// Generates the twin: profile from the seed (the case's unless `seed` is given), then all stages.
// Bit for bit reproducible for a given case and seed.
TwinRun run_twin(const TwinCase& c, std::optional<std::uint64_t> seed = std::nullopt);

}  // namespace rockdem::vlab
