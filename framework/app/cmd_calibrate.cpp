// `rockdem calibrate --data FILE.csv --law LAW [--effects a,b] [--fix p=v ...] [--free p ...]
// [--case CASE.toml] [--json OUT] [--save-model MODEL.csv] [--overwrite]`: fits the law's (and effects') free
// parameters to a measured record (framework/analysis/calibration.hpp) and prints the parameter
// table (value +- standard error, unit, at-bound flag), the NRMSE as `rockdem compare` defines it
// and the fit status. Without --case the stages and shear paths come from the record itself.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>

#include "framework/analysis/calibration.hpp"
#include "framework/app/calibration_inputs.hpp"
#include "framework/app/command.hpp"
#include "framework/app/result_files.hpp"
#include "framework/lab/lab_case.hpp"
#include "framework/core/error.hpp"
#include "framework/plugin_api/joint_law.hpp"

namespace rockdem {

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
      auto profile = std::make_shared<std::string>("poor");
      sub.add_option("--profile", *profile,
                     "profile-likelihood 95 % intervals: none, poor (the parameters whose standard error says little: at a "
                     "bound, not identifiable, or a linearised interval past a bound) or all")
          ->check(CLI::IsMember({"none", "poor", "all"}))
          ->capture_default_str();
      sub.add_flag("--quiet", *quiet, "print nothing but errors");
      auto overwrite = std::make_shared<bool>(false);
      sub.add_flag("--overwrite", *overwrite, "replace the files --json and --save-model write if they exist");
      return [=]() -> int {
        if (data->empty()) throw InputError("rockdem calibrate: --data MEASURED.csv is required");
        if (law->empty()) {
          throw InputError("rockdem calibrate: --law LAW is required; valid laws: " + JointLawRegistry::instance().names_joined());
        }
        if (*overwrite && json->empty() && save_model->empty())
          throw InputError("rockdem calibrate: --overwrite goes with --json or --save-model (it replaces their files)");
        // Known before the fit, which may take minutes.
        ResultFilePlan plan;
        plan.input("--data", *data);
        plan.input("--case", *case_file);
        plan.output("--json", *json);
        plan.output("--save-model", *save_model);
        if (!case_file->empty() && std::filesystem::exists(*case_file))
          plan.inputs("a drive file of --case", read_lab_test(*case_file).drive_files);
        plan.check(*overwrite);
        CalibrationOptions o = *opt;
        o.profile = *profile == "none" ? CalibrationOptions::Profile::none
                    : *profile == "all" ? CalibrationOptions::Profile::all
                                        : CalibrationOptions::Profile::poor;
        CalibrationInputs in{*law, *effects, *case_file, *fixes, *frees, *sets, {}};
        const MeasurementFile d = read_measurement_csv(*data);
        std::vector<std::string> notes;
        apply_inputs(*data, d, in, o, notes);
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
          write_json_result(*json, j);
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
