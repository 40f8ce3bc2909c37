// `rockdem compare --data MEASURED.csv --model MODEL.csv [--json OUT] [--plot DIR] [--overwrite] [--quiet]`, or
// `--case CASE.toml` instead of --model to run the laboratory-test case as an element test first:
// aligns a model record on a measured one by shear displacement (framework/analysis/compare.hpp),
// prints the error table and the worst segments in words, writes the JSON and, with --plot, the
// two-panel figure through scripts/plot_compare.py (Debian's /usr/bin/python3, which has
// matplotlib; the first python3 on PATH may be a virtual environment without it).
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <fstream>
#include <memory>

#include "framework/analysis/compare.hpp"
#include "framework/app/command.hpp"
#include "framework/app/result_files.hpp"
#include "framework/app/plot_scripts.hpp"
#include "framework/core/error.hpp"
#include "framework/lab/lab_case.hpp"
#include "framework/io/measurement_csv.hpp"

namespace rockdem {
namespace {

namespace fs = std::filesystem;

std::string meta(const MeasurementFile& f, const std::string& key) {
  for (const auto& [k, v] : f.metadata)
    if (k == key) return v;
  return {};
}

const CommandRegistrar reg{Command{
    "compare", "compare a model record with a measured one (aligned on shear displacement): errors by stage, "
               "cycle and quadrant",
    false, [](CLI::App& sub) {
      auto data = std::make_shared<std::string>();
      auto model = std::make_shared<std::string>();
      auto case_file = std::make_shared<std::string>();
      auto save_model = std::make_shared<std::string>();
      auto json = std::make_shared<std::string>();
      auto plot = std::make_shared<std::string>();
      auto quiet = std::make_shared<bool>(false);
      auto opt = std::make_shared<CompareOptions>();
      sub.add_option("--data", *data, "measured record (measurement CSV); required");
      sub.add_option("--model", *model, "model record (measurement CSV, e.g. from rockdem element)");
      sub.add_option("--case", *case_file, "laboratory-test case to run as an element test instead of --model");
      sub.add_option("--save-model", *save_model, "with --case: write the model record here");
      sub.add_option("--json", *json, "write the full comparison as JSON to this file");
      sub.add_option("--plot", *plot, "write the figure <model name>.png into this folder");
      auto overwrite = std::make_shared<bool>(false);
      sub.add_flag("--overwrite", *overwrite, "replace the files --json, --save-model and --plot write if they exist");
      sub.add_flag("--quiet", *quiet, "print nothing but errors");
      sub.add_option("--reversal-fraction", opt->segmentation.reversal_fraction,
                     "reversal threshold as a fraction of each stage's displacement range")
          ->check(CLI::Range(1e-6, 0.5))
          ->capture_default_str();
      sub.add_option("--endpoint-tolerance", opt->endpoint_tolerance,
                     "allowed difference of extremes and turning points, fraction of the stage's amplitude")
          ->check(CLI::Range(0.0, 1.0))
          ->capture_default_str();
      return [=]() -> int {
        // Checked here rather than by CLI11 so that every bad input exits with 2 and a sentence.
        if (data->empty()) throw InputError("rockdem compare: --data MEASURED.csv is required");
        if (model->empty() == case_file->empty()) {
          throw InputError("rockdem compare: give --model FILE.csv or --case CASE.toml" +
                           std::string(model->empty() ? "" : ", not both"));
        }
        if (!save_model->empty() && case_file->empty()) {
          throw InputError("rockdem compare: --save-model goes with --case (with --model the record is already a file)");
        }
        if (*overwrite && plot->empty() && json->empty() && save_model->empty())
          throw InputError("rockdem compare: --overwrite goes with --json, --save-model or --plot (it replaces their files)");
        ResultFilePlan plan;
        plan.input("--data", *data);
        plan.input("--model", *model);
        plan.input("--case", *case_file);
        plan.output("--json", *json);
        plan.output("--save-model", *save_model);
        // --plot DIR is a folder many comparisons may share (one figure per model, as scripts/demo
        // uses it), so it is not emptied; but a file of an earlier comparison is never replaced
        // unless the user says so, and that is known before the element test runs.
        if (!plot->empty()) {
          const std::string stem = fs::path(case_file->empty() ? *model : *case_file).stem().string();
          std::vector<fs::path> mine = {fs::path(*plot) / (stem + ".png")};
          if (!case_file->empty() && save_model->empty()) mine.push_back(fs::path(*plot) / (stem + ".csv"));
          std::error_code ec;
          if (fs::exists(*plot, ec) && !fs::is_directory(*plot, ec))
            throw InputError("--plot " + *plot + ": exists and is not a folder");
          for (const fs::path& f : mine)
            if (!*overwrite && fs::exists(f, ec))
              throw InputError("--plot " + *plot + ": '" + f.filename().string() + "' exists (an earlier comparison's); "
                               "add --overwrite to replace it, or give another folder");
          for (const fs::path& f : mine) plan.output("--plot", f.string(), true);
        }
        // The case is read first: the drive files it names are inputs too.
        std::optional<LabTest> test;
        if (!case_file->empty() && fs::exists(*case_file)) {
          test.emplace(read_lab_test(*case_file));
          plan.inputs("a drive file of --case", test->drive_files);
        }
        plan.check(*overwrite);
        const auto t0 = std::chrono::steady_clock::now();
        const MeasurementFile d = read_measurement_csv(*data);
        MeasurementFile m;
        std::string model_csv = *model;  // the model record on disk (the plot script reads files)
        double ms_run = 0.0;
        if (!case_file->empty()) {
          ElementRun run = run_element_test(*test);
          ms_run = run.wall_ms;
          m = std::move(run.record);
          model_csv = !save_model->empty() ? *save_model
                      : !plot->empty()     ? (fs::path(*plot) / (fs::path(*case_file).stem().string() + ".csv")).string()
                                           : std::string();
          if (!model_csv.empty()) {
            if (!plot->empty()) fs::create_directories(*plot);
            write_measurement_csv(model_csv, m);
          }
        } else {
          m = read_measurement_csv(*model);
        }
        const std::string model_name = case_file->empty() ? *model : *case_file;
        const auto t1 = std::chrono::steady_clock::now();
        Comparison c;
        try {
          c = compare(d, m, *opt);
        } catch (const InputError& e) {
          throw InputError(*data + " vs " + model_name + ": " + e.what());
        }
        // The table below and the JSON never show an RMSE of inf or nan.
        require_finite_result(to_json(c), *data + " vs " + model_name);
        const auto t2 = std::chrono::steady_clock::now();
        const double ms_read = std::chrono::duration<double, std::milli>(t1 - t0).count();
        const double ms_cmp = std::chrono::duration<double, std::milli>(t2 - t1).count();
        if (!json->empty()) {
          nlohmann::json j = to_json(c);
          j["data"] = *data;
          j["model"] = model_name;
          if (!case_file->empty()) j["model_record"] = model_csv;
          j["specimen"] = meta(d, "specimen");
          j["data_source"] = meta(d, "source");
          j["model_description"] = meta(m, "joint_model");
          write_json_result(*json, j);
        }
        if (!*quiet) {
          std::printf("compare: %s (%zu rows, %zu stage(s)) vs model %s (%zu rows), aligned on shear displacement\n",
                      data->c_str(), d.rows.size(), c.data_segments.stages.size(), model_name.c_str(), m.rows.size());
          if (!case_file->empty()) std::printf("(element test of %s run in %.1f ms)\n", case_file->c_str(), ms_run);
          std::printf("%s", format_table(c).c_str());
          for (const auto& n : c.notes) std::printf("note: %s\n", n.c_str());
          if (c.alignment.outside > 0) {
            std::printf("note: %zu measured rows lie beyond the ends of the model's matching segment (end value used)\n",
                        c.alignment.outside);
          }
          std::printf(c.worst.empty() ? "worst segments: none (no error above rounding)\n" : "worst segments:\n");
          for (const auto& w : c.worst) std::printf("  %s\n", w.c_str());
          std::printf("(read%s %.1f ms, compared in %.2f ms)\n", case_file->empty() ? "" : " and run", ms_read, ms_cmp);
        }
        if (!plot->empty()) {
          fs::create_directories(*plot);
          const fs::path png = fs::path(*plot) / (fs::path(model_name).stem().string() + ".png");
          const int rc = run_debian_python(
              {find_plot_script("plot_compare.py", "ROCKDEM_PLOT_COMPARE", "--plot").string(), *data, model_csv, "-o", png.string()},
              "--plot");
          if (rc != 0) throw std::runtime_error("--plot: plot_compare.py failed (exit " + std::to_string(rc) + ")");
          if (!*quiet) std::printf("figure: %s\n", png.c_str());
        }
        if (!*quiet && !json->empty()) std::printf("json: %s\n", json->c_str());
        return 0;
      };
    }}};

}  // namespace
}  // namespace rockdem
