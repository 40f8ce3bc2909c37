#pragma once
// A joint calibrated on a laboratory record, used as a case's joint: the JSON that
// `rockdem calibrate --json` or `rockdem diagnose --json` writes, read back into a law name, its
// parameter values and its effects, so that `[[joints]] calibration = "fit.json"` (and a lab
// case's `[joint] calibration`) makes the fitted joint the model's joint without copying numbers.
#include <string>
#include <vector>

#include "framework/core/params.hpp"
#include "framework/plugin_api/joint_law.hpp"

namespace rockdem {

struct CalibratedJoint {
  std::string file;    // the JSON file, as resolved
  std::string source;  // "calibrate" or "diagnose"
  std::string law;
  RawValues params;    // the law's, with where = "<file> params.<name>"
  std::vector<EffectSpec> effects;
};

// Reads `path` (named in messages as `where`, e.g. "case.toml:12 key 'joints.j.calibration'").
// calibrate JSON: law, effects, params {name: SI value}; diagnose JSON: base_law and
// final {effects, params} with effect parameters as "effect.param". Values are SI (angles in
// radians) and become quantities in the parameter's SI unit, so the law's own range checks apply.
// A missing file, malformed JSON, a law or effect rockdem does not know, or a parameter the law or
// effect does not have is an InputError naming the file and the entry.
CalibratedJoint read_calibrated_joint(const std::string& path, const std::string& where);

// Merges a case table's own joint entries over a calibration: `law` (if given) must be the
// calibration's; parameters given in the table replace the calibration's; an effect the table
// names that the calibration has takes the table's parameters over the calibration's, an effect
// it does not have is added after the calibration's.
void merge_calibration(const CalibratedJoint& c, std::string& law, const std::string& law_where,
                       RawValues& params, std::vector<EffectSpec>& effects);

}  // namespace rockdem
