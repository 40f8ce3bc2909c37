#pragma once
// The command-line glue of `rockdem calibrate` and `rockdem diagnose`: from what the user typed
// to CalibrationOptions (framework/analysis/calibration.hpp).
#include <string>
#include <vector>

#include "framework/analysis/calibration.hpp"

namespace rockdem {

// What `rockdem calibrate` and `rockdem diagnose` read from their command lines: the law, the
// effects as a comma list, a laboratory case (its stages, paths, element settings and, for the
// same law, its parameters as starting values), --fix NAME=VALUE, --free NAME, --set NAME=VALUE
// (a value that is not fitted, e.g. dilation=reversible; effect parameters as effect.param).
struct CalibrationInputs {
  std::string law, effects, case_file;
  std::vector<std::string> fix, free, set;
  // Effects whose parameters --set may name besides those in `effects`: diagnose's effects to try
  // (its `effects` is empty: the base law is fitted alone first), each set value used whenever that
  // effect is in a fitted chain.
  std::vector<std::string> settable_effects;
};
// Fills `opt` (law, effects, fixes, element settings, stages) from them; notes say what of a case
// is not used. InputErrors name the option and list what is valid.
void apply_inputs(const std::string& data_file, const MeasurementFile& data, const CalibrationInputs& in,
                  CalibrationOptions& opt, std::vector<std::string>& notes);

}  // namespace rockdem
