// `rockdem run CASE.toml [--out DIR]`, or `--default` for the built-in direct-shear case.
#include <filesystem>

#include "framework/app/command.hpp"
#include "framework/app/run_case.hpp"
#include "framework/core/error.hpp"
#include "rockdem_default_case.hpp"

namespace rockdem {
namespace {

namespace fs = std::filesystem;

const CommandRegistrar reg{Command{
    "run", "run a DEM case file (or the built-in default direct-shear case)", false,
    [](CLI::App& sub) {
      auto file = std::make_shared<std::string>();
      auto out = std::make_shared<std::string>();
      auto use_default = std::make_shared<bool>(false);
      auto quiet = std::make_shared<bool>(false);
      sub.add_option("case", *file, "case file (TOML)");
      sub.add_option("--out", *out, "output folder (default: rockdem-output/<case name>)");
      sub.add_flag("--default", *use_default, "run the built-in direct-shear case (test 9, 3 MPa, Coulomb slip)");
      sub.add_flag("--quiet", *quiet, "no progress output");
      auto restart = std::make_shared<std::string>();
      sub.add_option("--restart", *restart,
                     "continue from a stage checkpoint (stage_<n>_<name>.h5) written by an earlier run of the same case");
      return [file, out, use_default, quiet, restart]() -> int {
        if (file->empty() && !*use_default) throw InputError("rockdem run: give a case file, or --default for the built-in case");
        Case c = *use_default ? load_case_text(kDefaultCaseText, "built-in default case (cases/direct_shear/test09_coulomb.toml)", ".")
                              : load_case(*file);
        const std::string stem = *use_default ? "default" : fs::path(*file).stem().string();
        const fs::path dir = out->empty() ? fs::path("rockdem-output") / stem : fs::path(*out);
        if (!restart->empty() && !fs::exists(*restart))
          throw InputError("--restart " + *restart + ": checkpoint file does not exist");
        run_case(c, dir, *quiet, *restart);
        return 0;
      };
    }}};

}  // namespace
}  // namespace rockdem
