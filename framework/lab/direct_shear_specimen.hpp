#pragma once
// The DEM model of a laboratory direct-shear test: the report's Figure 4-7 specimen (Hsiung et
// al., CNWRA, section 4) built from a laboratory-test case file (lab_case.hpp). Two deformable
// elastic blocks of the test's rock (Table 4-1): the bottom one fixed, the top one (as long as
// the joint) loaded by the normal stress on its top face and pushed through frictionless
// interfaces by two rigid loading blocks, one against each end, that follow the stage's shear path
// together (the report's single block pulled the top block back through a non-separating
// interface; pushing from both sides keeps the interface free of tension, see the .cpp). The joint
// between the halves has the test's law, effects and parameters, per stage where the test has them.
// Per test stage k the case has two stages: `load_k` (normal stress applied, loading block held,
// run to equilibrium) and `shear_k` (the path); the record has one stage per test stage.
#include <string>

#include <toml++/toml.h>

#include "framework/io/case.hpp"
#include "framework/lab/lab_case.hpp"

namespace rockdem {

struct DirectShearOptions {
  // Overrides of the case's [dem] values; negative = keep the case's.
  double shear_velocity = -1.0;   // 0: the stages' own (laboratory) velocities [m/s]
  double mass_scaling_dt = -1.0;  // 0: real masses [s]
  int stages = 0;                 // run only the first n test stages (0: all)
};

// The DEM case as a TOML table (what `rockdem run --write-case` prints): every key of it is an
// ordinary case-file key (docs/case-files.md).
toml::table direct_shear_case_table(const LabTest& test, const DirectShearOptions& options = {});

// The same, loaded as a Case ready to run.
Case direct_shear_case(const LabTest& test, const DirectShearOptions& options = {});

}  // namespace rockdem
