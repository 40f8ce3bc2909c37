// `rockdem virtual-lab CASE.toml [--out FILE.csv] [--seed N]`: generates a synthetic measurement
// twin of a laboratory direct-shear test with the virtual lab's physically based joint model
// (framework/lab/virtual_lab/, docs/virtual-lab.md) and writes it in the measurement format, labelled
// `source: synthetic`, with its seed and model parameters. Bit for bit reproducible per seed.
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <vector>
#include <algorithm>

#include "framework/app/command.hpp"
#include "framework/app/result_files.hpp"
#include "framework/core/error.hpp"
#include "framework/io/measurement_csv.hpp"
#include "framework/lab/virtual_lab/twin.hpp"

namespace rockdem {
namespace {

const CommandRegistrar reg{Command{
    "virtual-lab",
    "generate a synthetic measurement twin of a direct-shear test (rough profiles, facet friction, wear)", false,
    [](CLI::App& sub) {
      auto file = std::make_shared<std::string>();
      auto out = std::make_shared<std::string>();
      auto seed = std::make_shared<long long>(-1);
      auto quiet = std::make_shared<bool>(false);
      sub.add_option("case", *file, "virtual-lab case file (TOML), e.g. cases/virtual_lab/test09.toml")->required();
      sub.add_option("--out", *out, "output CSV (default: <case name>.csv in the current folder)");
      sub.add_option("--seed", *seed, "seed of the profile and the noise (default: the case's seed)")
          ->check(CLI::Range(0LL, 2147483647LL));
      sub.add_flag("--quiet", *quiet, "no summary on standard output");
      auto overwrite = std::make_shared<bool>(false);
      sub.add_flag("--overwrite", *overwrite, "replace the output CSV if it exists");
      return [file, out, seed, quiet, overwrite]() -> int {
        const std::string path =
            out->empty() ? std::filesystem::path(*file).stem().string() + ".csv" : *out;
        ResultFilePlan plan;
        plan.input("the case file", *file);
        plan.output(out->empty() ? "the default --out" : "--out", path);
        const vlab::TwinCase c = vlab::read_twin_case(*file);
        plan.check(*overwrite);  // before the twin is made
        std::optional<std::uint64_t> s;
        if (*seed >= 0) s = static_cast<std::uint64_t>(*seed);
        const vlab::TwinRun r = vlab::run_twin(c, s);
        write_measurement_csv(path, r.record);
        if (!*quiet) {
          std::printf("%s: synthetic twin, seed %llu, profile JRC %.2f, %zu stage(s), %ld steps in %.1f ms -> %s (%zu rows)\n",
                      c.specimen.c_str(), static_cast<unsigned long long>(r.seed), r.profile_jrc, c.stages.size(),
                      r.steps, r.wall_ms, path.c_str(), r.record.rows.size());
          // Per stage: the strength both ways and the dilation reached and kept (calibration).
          std::vector<double> peak(c.stages.size(), 0.0), trough(c.stages.size(), 0.0),
              dil_max(c.stages.size(), 0.0), dil_end(c.stages.size(), 0.0);
          for (const auto& row : r.record.rows) {
            const auto k = static_cast<std::size_t>(row.stage - 1);
            peak[k] = std::max(peak[k], row.shear_stress_MPa);
            trough[k] = std::min(trough[k], row.shear_stress_MPa);
            dil_max[k] = std::max(dil_max[k], row.normal_disp_mm);
            dil_end[k] = row.normal_disp_mm;
          }
          for (std::size_t k = 0; k < c.stages.size(); ++k) {
            std::printf("  stage %zu at %.3g MPa: peak %+.3f / %+.3f MPa, dilation max %.3f mm, at the end %.3f mm\n", k + 1,
                        c.stages[k].normal_stress * 1e-6, peak[k], trough[k], dil_max[k], dil_end[k]);
          }
        }
        return 0;
      };
    }}};

}  // namespace
}  // namespace rockdem
