// `rockdem element CASE.toml [--out FILE.csv] [--overwrite]`: drives one joint point through the stages of a
// laboratory direct-shear test (framework/lab/lab_case.hpp: the case file; element_driver.hpp: the
// driver) and writes the result in the measurement format.
#include <cstdio>
#include <filesystem>
#include <memory>

#include "framework/app/command.hpp"
#include "framework/app/result_files.hpp"
#include "framework/core/error.hpp"
#include "framework/lab/lab_case.hpp"
#include "framework/io/measurement_csv.hpp"

namespace rockdem {
namespace {

namespace fs = std::filesystem;

const CommandRegistrar reg{Command{
    "element", "drive one joint point through a direct-shear path (element test) and write a measurement CSV", false,
    [](CLI::App& sub) {
      auto file = std::make_shared<std::string>();
      auto out = std::make_shared<std::string>();
      auto quiet = std::make_shared<bool>(false);
      sub.add_option("case", *file, "laboratory-test case file (TOML), e.g. cases/direct_shear/test09_mohr_coulomb.toml")->required();
      sub.add_option("--out", *out, "output CSV (default: <case name>.csv in the current folder)");
      sub.add_flag("--quiet", *quiet, "no summary on standard output");
      auto overwrite = std::make_shared<bool>(false);
      sub.add_flag("--overwrite", *overwrite, "replace the output CSV if it exists");
      return [file, out, quiet, overwrite]() -> int {
        const std::string path = out->empty() ? fs::path(*file).stem().string() + ".csv" : *out;
        ResultFilePlan plan;
        plan.input("the case file", *file);
        plan.output(out->empty() ? "the default --out" : "--out", path);
        const LabTest c = read_lab_test(*file);
        plan.inputs("a drive file of the case", c.drive_files);
        plan.check(*overwrite);  // before the element test runs
        const ElementRun run = [&] {
          try {
            return run_element_test(c);
          } catch (const InputError& e) {
            throw InputError(*file + ": " + e.what());
          }
        }();
        const MeasurementFile& mf = run.record;
        const double ms = run.wall_ms;
        try {
          write_measurement_csv(path, mf);
        } catch (const InputError& e) {
          throw InputError(*file + ": " + e.what());
        }
        if (!*quiet) {
          std::printf("%s: %s, %zu stage(s), %ld increments in %.1f ms -> %s (%zu rows)\n", c.specimen.c_str(),
                      c.model->description().c_str(), c.stages.size(), run.increments, ms, path.c_str(),
                      mf.rows.size());
          for (std::size_t si = 0; si < c.stages.size(); ++si) {
            double tmax = -1e300, tmin = 1e300, dmax = -1e300;
            for (const auto& r : mf.rows) {
              if (r.stage != static_cast<int>(si) + 1) continue;
              tmax = std::max(tmax, r.shear_stress_MPa);
              tmin = std::min(tmin, r.shear_stress_MPa);
              dmax = std::max(dmax, r.normal_disp_mm);
            }
            std::printf("  stage %zu: sigma_n %.3f MPa, shear stress %+.4f .. %+.4f MPa, max normal disp %.4f mm\n",
                        si + 1, c.stages[si].normal_stress / 1e6, tmin, tmax, dmax);
          }
          if (run.unconverged > 0) {
            std::printf("  warning: %ld increments did not meet the stage's normal condition (normal stress or stiffness)\n", run.unconverged);
          }
        }
        return 0;
      };
    }}};

}  // namespace
}  // namespace rockdem
