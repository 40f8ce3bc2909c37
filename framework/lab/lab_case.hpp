#pragma once
// A laboratory direct-shear test as a case file: the specimen, the joint law with its parameters,
// and the normal-stress stages with their shear paths. The same file runs as an element test
// (`rockdem element`: one joint point, framework/lab/element_driver.hpp) and as the full DEM
// specimen (`rockdem run`: framework/lab/direct_shear_specimen.hpp). Keys (docs/case-files.md):
//   title = "..."
//   [specimen]      name, joint_length; density, bulk, shear (rock matrix, needed by the DEM run)
//   [element]       step, output_every, frame_stiffness, frame_mass
//   [dem]           zone_size, rounding, shear_velocity, mass_scaling_dt, dt_safety, history_interval
//   [joint]         law = "<name>", effects = [...]; [joint.params] the law's parameters
//   [[stage]]       normal_stress, normal_control, normal_stiffness, path = cycles | sinusoid | file
//                   and its keys; optional [stage.params] overriding law parameters from that stage
// Every mistake is an InputError naming file:line and key, what is wrong and what is valid.
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <toml++/toml.h>

#include "framework/io/measurement_csv.hpp"
#include "framework/lab/element_driver.hpp"

namespace rockdem {

// Rock matrix of the specimen (the report's Table 4-1), elastic.
struct SpecimenRock {
  double density = 0.0;  // [kg/m^3]
  double bulk = 0.0;     // [Pa]
  double shear = 0.0;    // [Pa]
};

// Settings of the DEM specimen built from a laboratory test (direct_shear_specimen.hpp).
struct DemSettings {
  double zone_size = 0.01;       // [m]
  double rounding = 5e-4;        // corner rounding length [m]
  double detection_tolerance = 5e-3;  // contacts are found this far beyond the rounding [m]
  double shear_velocity = 0.0;   // cycles paths run at this speed instead of the stage's (0: the stage's) [m/s]
  double mass_scaling_dt = 0.0;  // scale inertial masses so that this step is stable (0: real masses) [s]
  double dt_safety = 0.5;
  int history_interval = 100;    // steps between samples of the joint record
};

struct LabTest {
  std::string file;      // the case file (for messages and metadata)
  std::string title;
  std::string specimen;  // name written to the record ('# specimen:')
  double joint_length = 1.0;  // [m]
  double step = 1e-5;         // element driver: largest shear increment [m]
  int output_every = 1;
  double frame_stiffness = 0.0;  // element driver: compliant loading frame [Pa/m] (0: rigid)
  double frame_mass = 0.0;       // element driver: top-block mass per unit joint area [kg/m^2]
  std::optional<SpecimenRock> rock;
  DemSettings dem;
  // The joint as written, for models built elsewhere (the DEM specimen copies these tables).
  std::string law;
  toml::table joint_params;                // [joint.params]
  toml::array effects;                     // [joint] effects
  std::vector<toml::table> stage_params;   // [stage.params] per stage (empty table: none)
  // Built and checked: the joint model, per-stage models for stages with params, the stages.
  std::unique_ptr<JointModel> model;
  std::vector<std::unique_ptr<JointModel>> stage_models;
  std::vector<ElementStage> stages;
  // The drive files its stages read (path = "file"), as found from the case's folder: inputs a
  // command must not write over.
  std::vector<std::string> drive_files;
};

// Reads and checks a laboratory-test case file.
LabTest read_lab_test(const std::string& path);

// The [[stage]] tables of a test file (at least one; InputError otherwise).
const toml::array& stage_tables(const toml::table& root, const std::string& file);

// One [[stage]] table's normal condition and shear path (not its params). `path` names the table
// in messages (e.g. "stage[2]"); `extra_keys` are further keys the caller handles itself. Relative
// drive files are taken from the folder of `file`.
ElementStage read_stage(const toml::table& t, const std::string& file, const std::string& path,
                        const std::vector<std::string>& extra_keys = {});

// A shear-displacement drive: (time [s] from the first row, offset [m]). The file is either a
// measurement-format record (rows of `stage`, or all when stage = 0) or a drive table with the
// columns time_s and shear_disp_mm after optional '# key: value' lines.
ShearPath read_shear_drive(const std::string& path, int stage, const std::string& where);

// True if the file looks like a laboratory-test case ([joint] and [[stage]], no [[blocks]]).
bool is_lab_test_file(const std::string& path);

struct ElementRun {
  MeasurementFile record;
  long increments = 0;
  long unconverged = 0;  // increments whose normal solve did not meet the normal condition
  double wall_ms = 0.0;
};

// Runs the test as an element test: all stages on one joint point, the record in the
// measurement format (metadata: specimen, joint length, source rockdem, model element).
ElementRun run_element_test(const LabTest& test);

}  // namespace rockdem
