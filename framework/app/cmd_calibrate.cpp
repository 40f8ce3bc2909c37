// `rockdem calibrate --data FILE.csv --law LAW [--effects a,b] [--fix p=v ...] [--free p ...]
// [--case CASE.toml] [--json OUT] [--save-model MODEL.csv]`: fits the law's (and effects') free
// parameters to a measured record (framework/analysis/calibration.hpp) and prints the parameter
// table (value +- standard error, unit, at-bound flag), the NRMSE as `rockdem compare` defines it
// and the fit status. Without --case the stages and shear paths come from the record itself.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <sstream>

#include "framework/analysis/calibration.hpp"
#include "framework/app/command.hpp"
#include "framework/core/error.hpp"
#include "framework/io/lab_test.hpp"
#include "framework/io/toml_values.hpp"
#include "models/joint_laws/joint_law.hpp"

namespace rockdem {

// Shared with `rockdem diagnose`: the options both commands read from a record or a case.
void calibration_inputs(const std::string& data_file, const MeasurementFile& data, const std::string& case_file,
                        CalibrationOptions& opt, std::vector<std::string>& notes);

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
void set_value(const std::string& arg, CalibrationOptions& o) {
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
  if (std::find(o.effects.begin(), o.effects.end(), effect) == o.effects.end()) {
    throw InputError("--set " + arg + ": effect '" + effect + "' is not in --effects");
  }
  o.effect_values[effect][name.substr(dot + 1)] = raw;
}

}  // namespace

void calibration_inputs(const std::string& data_file, const MeasurementFile& data, const std::string& case_file,
                        CalibrationOptions& opt, std::vector<std::string>& notes) {
  if (data.rows.size() < 2) throw InputError(data_file + ": the record has fewer than two rows; nothing to calibrate");
  JointLawRegistry::instance().get(opt.law, "joint law", "--law");
  for (const auto& e : opt.effects) EffectRegistry::instance().get(e, "effect", "--effects");
  double length = 1.0;
  for (const auto& [k, v] : data.metadata)
    if (k == "joint_length_m") length = std::stod(v);
  opt.element.length = length;
  opt.element.max_step = 1e-5;  // the laboratory cases' element step, 0.01 mm
  if (case_file.empty()) return;
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

namespace {

const CommandRegistrar reg{Command{
    "calibrate", "fit a joint law (and effects) to a measured record: parameters with standard errors, NRMSE as compare",
    false, [](CLI::App& sub) {
      auto data = std::make_shared<std::string>();
      auto law = std::make_shared<std::string>();
      auto effects = std::make_shared<std::string>();
      auto fixes = std::make_shared<std::vector<std::string>>();
      auto frees = std::make_shared<std::vector<std::string>>();
      auto sets = std::make_shared<std::vector<std::string>>();
      auto case_file = std::make_shared<std::string>();
      auto json = std::make_shared<std::string>();
      auto save_model = std::make_shared<std::string>();
      auto quiet = std::make_shared<bool>(false);
      auto opt = std::make_shared<CalibrationOptions>();
      sub.add_option("--data", *data, "measured record (measurement CSV); required");
      sub.add_option("--law", *law, "joint law to fit (rockdem laws); required");
      sub.add_option("--effects", *effects, "effects composed with the law, in order: a,b");
      sub.add_option("--fix", *fixes, "fix a parameter: p=VALUE with its unit, e.g. friction=\"30 deg\"; effect "
                                      "parameters as effect.param")->take_all();
      sub.add_option("--free", *frees, "fit a parameter that is fixed by default (e.g. kn, cohesion)")->take_all();
      sub.add_option("--set", *sets, "set a parameter that is not fitted (a choice or flag), e.g. dilation=reversible; "
                                      "effect parameters as effect.param")->take_all();
      sub.add_option("--case", *case_file, "laboratory-test case: its stages, paths and parameters as starting values");
      sub.add_option("--json", *json, "write the result as JSON");
      sub.add_option("--save-model", *save_model, "write the fitted model's record (measurement CSV)");
      sub.add_option("--loss-scale", opt->loss_scale, "soft-L1 scale as a fraction of each variable's range (0: least squares)")
          ->check(CLI::Range(0.0, 10.0))->capture_default_str();
      sub.add_option("--fit-step", opt->fit_step, "element-driver step while fitting [m]")->check(CLI::Range(1e-7, 1e-2))->capture_default_str();
      sub.add_option("--max-iterations", opt->max_iterations, "Levenberg-Marquardt iterations")->check(CLI::Range(1, 1000))->capture_default_str();
      sub.add_option("--threads", opt->threads, "threads for the finite-difference Jacobian")->check(CLI::Range(1, 64))->capture_default_str();
      sub.add_flag("--quiet", *quiet, "print nothing but errors");
      return [=]() -> int {
        if (data->empty()) throw InputError("rockdem calibrate: --data MEASURED.csv is required");
        if (law->empty()) {
          throw InputError("rockdem calibrate: --law LAW is required; valid laws: " + JointLawRegistry::instance().names_joined());
        }
        CalibrationOptions o = *opt;
        o.law = *law;
        o.effects = split_list(*effects);
        o.free = *frees;
        for (const auto& f : *fixes) {
          const auto eq = f.find('=');
          if (eq == std::string::npos || eq == 0 || eq + 1 == f.size()) {
            throw InputError("--fix " + f + ": write NAME=VALUE, e.g. --fix friction=\"30 deg\"");
          }
          o.fix_text[f.substr(0, eq)] = f.substr(eq + 1);
        }
        const MeasurementFile d = read_measurement_csv(*data);
        std::vector<std::string> notes;
        calibration_inputs(*data, d, *case_file, o, notes);
        for (const auto& a : *sets) set_value(a, o);
        const Segmentation seg = segment(d, o.compare.segmentation);
        CalibrationResult r;
        try {
          r = calibrate(d, seg, o);
        } catch (const InputError& e) {
          throw InputError(*data + ": " + e.what());
        }
        if (!save_model->empty()) write_measurement_csv(*save_model, r.model);
        if (!json->empty()) {
          nlohmann::json j = to_json(r);
          j["data"] = *data;
          if (!case_file->empty()) j["case"] = *case_file;
          j["notes"] = notes;
          std::ofstream out(*json);
          if (!out) throw InputError(*json + ": cannot open for writing");
          out << j.dump(2) << '\n';
          if (!out) throw InputError(*json + ": write failed");
        }
        if (!*quiet) {
          std::printf("calibrate: %s (%zu rows, %zu stage(s)), model %s\n", data->c_str(), d.rows.size(), seg.stages.size(),
                      r.model_description.c_str());
          for (const auto& n : notes) std::printf("note: %s\n", n.c_str());
          std::printf("%s", format_table(r).c_str());
          if (!json->empty()) std::printf("json: %s\n", json->c_str());
        }
        return 0;
      };
    }}};

}  // namespace
}  // namespace rockdem
