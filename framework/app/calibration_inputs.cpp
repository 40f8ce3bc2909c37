#include "framework/app/calibration_inputs.hpp"

#include <algorithm>
#include <cstdlib>
#include <sstream>

#include "framework/core/did_you_mean.hpp"
#include "framework/core/error.hpp"
#include "framework/core/names.hpp"
#include "framework/io/toml_values.hpp"
#include "framework/lab/lab_case.hpp"
#include "framework/plugin_api/joint_law.hpp"

namespace rockdem {
namespace {

std::vector<std::string> split_list(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream ss(s);
  std::string item;
  while (std::getline(ss, item, ',')) {
    const auto b = item.find_first_not_of(' '), e = item.find_last_not_of(' ');
    if (b != std::string::npos) out.push_back(item.substr(b, e - b + 1));
  }
  return out;
}

// --set NAME=VALUE: a raw value for the law or an effect ("effect.param"), checked when the model
// is built (an unknown name or value is an InputError listing the valid ones).
void set_value(const std::string& arg, const std::vector<std::string>& settable_effects, CalibrationOptions& o) {
  const auto eq = arg.find('=');
  if (eq == std::string::npos || eq == 0 || eq + 1 == arg.size()) {
    throw InputError("--set " + arg + ": write NAME=VALUE, e.g. --set dilation=reversible");
  }
  std::string name = arg.substr(0, eq);
  const std::string text = arg.substr(eq + 1);
  RawValue raw;
  raw.where = "--set " + arg;
  char* end = nullptr;
  const double num = std::strtod(text.c_str(), &end);
  if (text == "true" || text == "false") raw.value = text == "true";
  else if (end != text.c_str() && *end == '\0') raw.value = num;
  else raw.value = text;
  const auto dot = name.find('.');
  if (dot == std::string::npos) {
    o.law_values[name] = raw;
    return;
  }
  const std::string effect = name.substr(0, dot);
  std::vector<std::string> known = o.effects;
  for (const auto& e : settable_effects)
    if (std::find(known.begin(), known.end(), e) == known.end()) known.push_back(e);
  if (std::find(known.begin(), known.end(), effect) == known.end()) {
    const std::string where = settable_effects.empty() ? "in --effects" : "among the effects tried";
    throw InputError("--set " + arg + ": effect '" + effect + "' is not " + where + did_you_mean(effect, known) +
                     (known.empty() ? "; no effects were given (--effects NAME,...)" : "; valid: " + join_names(known)));
  }
  o.effect_values[effect][name.substr(dot + 1)] = raw;
}

// A laboratory case's stages, element settings and (same law) parameters as starting values.
void apply_case(const std::string& case_file, CalibrationOptions& opt, std::vector<std::string>& notes) {
  const LabTest test = read_lab_test(case_file);
  opt.stages = test.stages;
  bool per_stage = false;
  for (auto& s : opt.stages) {
    per_stage = per_stage || s.model != nullptr;
    s.model = nullptr;
  }
  if (per_stage) notes.push_back(case_file + ": per-stage parameters ([stage.params]) are not calibrated; one set is fitted to all stages");
  opt.element.max_step = test.step;
  opt.element.length = test.joint_length;
  opt.element.frame_stiffness = test.frame_stiffness;
  opt.element.frame_mass = test.frame_mass;
  if (test.law == opt.law) {
    opt.law_values = raw_values(test.joint_params, case_file, "joint.params");
  } else {
    notes.push_back(case_file + " is a " + test.law + " case; its parameters are not used as starting values for " + opt.law);
  }
  for (const auto& e : test.effects) {
    const auto* t = e.as_table();
    if (!t) continue;
    const auto* nm = t->get("name");
    if (!nm || !nm->is_string()) continue;
    const std::string name = nm->as_string()->get();
    if (std::find(opt.effects.begin(), opt.effects.end(), name) != opt.effects.end()) {
      opt.effect_values[name] = raw_values(*t, case_file, "joint.effects." + name, {"name"});
    }
  }
}

}  // namespace

void apply_inputs(const std::string& data_file, const MeasurementFile& data, const CalibrationInputs& in,
                  CalibrationOptions& opt, std::vector<std::string>& notes) {
  opt.law = in.law;
  opt.effects = split_list(in.effects);
  opt.free = in.free;
  for (const auto& f : in.fix) {
    const auto eq = f.find('=');
    if (eq == std::string::npos || eq == 0 || eq + 1 == f.size()) {
      throw InputError("--fix " + f + ": write NAME=VALUE, e.g. --fix friction=\"30 deg\"");
    }
    opt.fix_text[f.substr(0, eq)] = f.substr(eq + 1);
  }
  const std::string& case_file = in.case_file;
  if (data.rows.size() < 2) throw InputError(data_file + ": the record has fewer than two rows; nothing to calibrate");
  JointLawRegistry::instance().get(opt.law, "joint law", "--law");
  for (const auto& e : opt.effects) EffectRegistry::instance().get(e, "effect", "--effects");
  double length = 1.0;
  for (const auto& [k, v] : data.metadata)
    if (k == "joint_length_m") length = std::stod(v);
  opt.element.length = length;
  opt.element.max_step = 1e-5;  // the laboratory cases' element step, 0.01 mm
  if (!case_file.empty()) apply_case(case_file, opt, notes);
  for (const auto& a : in.set) set_value(a, in.settable_effects, opt);
}

}  // namespace rockdem
