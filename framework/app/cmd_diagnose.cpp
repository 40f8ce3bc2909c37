// `rockdem diagnose --data FILE.csv --law LAW [--json OUT.json] [--report DIR] [--overwrite]
// [--effects a,b] [--case CASE.toml] [--fix p=v] [--set p=v] [--threads N]`: calibrates the base law, says where
// it fails, which covariates the residual follows, which catalogue effect helps most (an IC with the effective number of independent residuals) and
// climbs the ladder of effects (framework/analysis/diagnosis.hpp). --report writes the aligned
// records and the figures through scripts/plot_diagnosis.py, run by Debian's /usr/bin/python3
// (which has matplotlib; the first python3 on PATH may be a virtual environment without it).

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <utility>

#include "framework/analysis/diagnosis.hpp"
#include "framework/app/calibration_inputs.hpp"
#include "framework/app/cli_contract.hpp"
#include "framework/app/command.hpp"
#include "framework/app/result_files.hpp"
#include "framework/lab/lab_case.hpp"
#include "framework/app/plot_scripts.hpp"
#include "framework/core/error.hpp"
#include "framework/io/output_folder.hpp"
#include "framework/plugin_api/joint_law.hpp"

namespace rockdem {
namespace {

namespace fs = std::filesystem;

const CommandRegistrar reg{Command{
    "diagnose", "calibrate a law, localise and explain its misfit, rank the catalogue effects by an information criterion and add them while it falls",
    false, [](CLI::App& sub) {
      auto data = std::make_shared<std::string>();
      auto in = std::make_shared<CalibrationInputs>();
      auto try_effects = std::make_shared<std::string>();
      auto json = std::make_shared<std::string>();
      auto report = std::make_shared<std::string>();
      auto quiet = std::make_shared<bool>(false);
      auto opt = std::make_shared<DiagnosisOptions>();
      sub.add_option("--data", *data, "measured record (measurement CSV); required");
      sub.add_option("--law", in->law,
                     "base joint law (rockdem laws), or 'best': the standard law and dilation mode that fit the record best; "
                     "required");
      sub.add_option("--effects", *try_effects, "effects to try, a,b (default: every physical effect registered)");
      sub.add_option("--case", in->case_file, "laboratory-test case: its stages, paths and starting parameters");
      sub.add_option("--fix", in->fix, "fix a base-law parameter: p=VALUE with its unit")->take_all();
      sub.add_option("--set", in->set, "set a parameter that is not fitted, e.g. dilation=reversible")->take_all();
      sub.add_option("--json", *json, "write the diagnosis as JSON");
      sub.add_option("--report", *report, "write figures and the aligned records into this folder (new or empty)");
      auto overwrite = std::make_shared<bool>(false);
      sub.add_flag("--overwrite", *overwrite,
                   "replace the --json file if it exists; empty the --report folder first (only one an earlier diagnose wrote)");
      sub.add_option("--threads", opt->threads, "threads (effects fitted in parallel)")->check(CLI::Range(1, 64))->capture_default_str();
      auto no_check = std::make_shared<bool>(false);
      sub.add_flag("--no-base-law-check", *no_check,
                   "do not fit the standard base laws and dilation modes first (faster; no warning when another fits "
                   "much better)");
      sub.add_flag("--fit-unjudged", opt->fit_unjudged,
                   "fit also the effects this record cannot reveal (reported, kept out of the ladder)");
      sub.add_flag("--quiet", *quiet, "print nothing but errors");
      return [=]() -> int {
        if (data->empty()) throw InputError("rockdem diagnose: --data MEASURED.csv is required");
        if (in->law.empty()) {
          throw InputError("rockdem diagnose: --law LAW is required; valid laws: " + JointLawRegistry::instance().names_joined() +
                           ", or best");
        }
        opt->check_base_laws = !*no_check;
        if (in->law == "best") {
          // The law is chosen after the record is read; a base-law parameter cannot be fixed or set
          // before it is known (--set of an effect's parameter, "effect.param", still can).
          if (*no_check) throw InputError("rockdem diagnose: --law best needs the base-law check; leave out --no-base-law-check");
          if (!in->fix.empty())
            throw InputError("rockdem diagnose --law best: --fix " + in->fix.front() +
                             ": a base-law parameter is fixed only with the law named (--law mohr_coulomb, barton_bandis, ...)");
          for (const auto& s : in->set)
            if (s.substr(0, s.find('=')).find('.') == std::string::npos)
              throw InputError("rockdem diagnose --law best: --set " + s +
                               ": a base-law setting is given only with the law named (--law mohr_coulomb, barton_bandis, ...)");
          opt->use_best_base_law = true;
          // Read the inputs (case stages, element settings, and the case's values) against the
          // case's own law, or a standard one; the check replaces it with the best and keeps only
          // the stiffnesses kn and ks, which that law has too.
          in->law = "mohr_coulomb";
          if (!in->case_file.empty() && fs::exists(in->case_file)) in->law = read_lab_test(in->case_file).law;
        }
        if (*overwrite && report->empty() && json->empty())
          throw InputError("rockdem diagnose: --overwrite goes with --json or --report (it replaces their files)");
        // The report folder's files are the report's own (diagnosis.json, the figures, manifest.json).
        if (!json->empty() && !report->empty() &&
            fs::weakly_canonical(fs::path(*json)).parent_path() == fs::weakly_canonical(fs::path(*report)))
          throw InputError("--json " + *json + ": is inside --report " + *report + ", whose files the report writes (its own "
                           "diagnosis.json among them); give --json another folder or leave it out");
        ResultFilePlan plan;
        plan.input("--data", *data);
        plan.input("--case", in->case_file);
        plan.output("--json", *json);
        if (!in->case_file.empty() && fs::exists(in->case_file))
          plan.inputs("a drive file of --case", read_lab_test(in->case_file).drive_files);
        plan.check(*overwrite);
        // The report folder is the diagnosis's own, as a run's --out is: checked before the fit
        // (which may take minutes), never mixed with an earlier report's figures, and marked with a
        // manifest saying which command made it (kind "diagnose report": --overwrite never
        // empties a run's folder, nor a folder that holds this command's own inputs).
        Manifest manifest;
        manifest.kind = "diagnose report";
        if (!report->empty()) {
          if (*overwrite) {
            for (const auto& [option, file] : {std::pair<std::string, std::string>{"--data", *data}, {"--case", in->case_file}}) {
              if (file.empty() || !fs::exists(*report)) continue;
              const fs::path f = fs::weakly_canonical(file), dir = fs::weakly_canonical(*report);
              if (std::mismatch(dir.begin(), dir.end(), f.begin(), f.end()).first == dir.end())
                throw InputError("--report " + *report + " --overwrite would empty the folder that holds " + option + " " +
                                 file + "; give the report another folder");
            }
          }
          prepare_output_folder(*report, *overwrite ? FolderUse::overwrite : FolderUse::fresh, "--report", manifest.kind);
          manifest.command_line = command_line();
          manifest.case_file = in->case_file;
          manifest.started_utc = utc_now();
          write_manifest(*report, manifest);
        }
        // A diagnosis that stops (bad data, a failed fit or plot) says so in its report's manifest.
        const auto close_report = [&](const std::string& status, int code) {
          if (!report->empty()) close_manifest(*report, manifest, status, code);
        };
        const auto work = [&]() -> int {
          DiagnosisOptions o = *opt;
          // Each fit as it finishes, on stderr (stdout holds the report): a long record takes minutes.
          if (!*quiet) o.progress = [](const std::string& line) { std::fprintf(stderr, "diagnose %s\n", line.c_str()); };
          const MeasurementFile d = read_measurement_csv(*data);
          std::vector<std::string> notes;
          CalibrationInputs list;
          list.law = in->law;
          list.effects = *try_effects;
          CalibrationOptions tried;
          apply_inputs(*data, d, list, tried, notes);
          o.effects = tried.effects;
          // --set effect.param: for any effect diagnose tries (the base law is fitted without effects).
          CalibrationInputs base_inputs = *in;
          base_inputs.settable_effects = o.effects.empty() ? physical_effects() : o.effects;
          apply_inputs(*data, d, base_inputs, o.base, notes);
          // Checked now: inside the diagnosis a value the effect refuses would only make its fit fail.
          for (const auto& [effect, values] : o.base.effect_values)
            EffectRegistry::instance().get(effect, "effect", "--set").make(values, "--set");
          const Segmentation seg = segment(d, o.base.compare.segmentation);
          Diagnosis dg;
          try {
            dg = diagnose(d, seg, o);
          } catch (const InputError& e) {
            throw InputError(*data + ": " + e.what());
          }
          nlohmann::json j = to_json(dg, *data);
          j["notes"] = notes;
          auto write_json = [&](const std::string& path) {
            write_json_result(path, j);
          };
          if (!json->empty()) write_json(*json);
          if (!*quiet) {
            std::printf("diagnose: %s (%zu rows, %zu stage(s)), base law %s, %.1f s\n", data->c_str(), d.rows.size(),
                        seg.stages.size(), dg.law.c_str(), dg.wall_ms / 1e3);
            for (const auto& n : notes) std::printf("note: %s\n", n.c_str());
            std::printf("%s", format_report(dg).c_str());
          }
          if (!report->empty()) {
            write_report_data(dg, d, *report);
            const std::string jpath = (fs::path(*report) / "diagnosis.json").string();
            write_json(jpath);
            const std::string script = find_plot_script("plot_diagnosis.py", "ROCKDEM_PLOT_DIAGNOSIS", "--report").string();
            if (run_debian_python({script, jpath, "--out", *report}, "--report") != 0) {
              throw std::runtime_error("--report: " + script + " failed (Debian's /usr/bin/python3 with python3-matplotlib; "
                                       "ROCKDEM_PLOT_DIAGNOSIS names another copy)");
            }
            close_report("finished", 0);
            if (!*quiet) std::printf("report: %s\n", report->c_str());
          }
          if (!*quiet && !json->empty()) std::printf("json: %s\n", json->c_str());
          return 0;
        };
        if (report->empty()) return work();
        try {
          return work();
        } catch (const InputError&) {
          try { close_report("failed", 2); } catch (const std::exception&) {}  // the first error is the one to report
          throw;
        } catch (const std::exception&) {
          try { close_report("failed", 1); } catch (const std::exception&) {}
          throw;
        }
      };
    }}};

}  // namespace
}  // namespace rockdem
