#pragma once
// Results the subcommands write (JSON summaries): never half-written (through a temporary file
// and a rename), and, where every number is a result (compare's errors), never with a NaN or inf
// in them (nlohmann would write it as null, and a reader would take it for "no value").
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

namespace rockdem {

// The JSON path of the first non-finite number in `j` ("" when all are finite), e.g.
// "/stages/0/rmse_shear_stress".
std::string first_nonfinite(const nlohmann::json& j, const std::string& at = "");

// Throws an InputError "<inputs>: the result is not finite (<path> = nan); ..." when `j` holds a
// non-finite number, so that the user hears which inputs to check instead of reading nulls.
void require_finite_result(const nlohmann::json& j, const std::string& inputs);

// Writes `j` (2-space indented) to `path` through path.tmp and a rename. Not every summary must
// be finite (a calibration's open parameter bounds are inf, written as null); the commands whose
// results must be call require_finite_result first.
void write_json_result(const std::string& path, const nlohmann::json& j);

}  // namespace rockdem


namespace rockdem {

// The files a command is about to write, checked before it works (a fit or a simulation may take
// minutes, and a result must never silently take the place of an earlier one): an output may not
// be one of the command's inputs nor another of its outputs, nor a folder, nor in a folder that
// does not exist; one that exists is replaced only when the user said --overwrite.
class ResultFilePlan {
 public:
  // A file the command reads (given with `option`, e.g. "--data"); "" is ignored.
  void input(const std::string& option, const std::string& path);
  // Several, e.g. the drive files a laboratory-test case reads (LabTest::drive_files).
  void inputs(const std::string& what, const std::vector<std::string>& paths) {
    for (const auto& p : paths) input(what, p);
  }
  // A file the command writes; "" is ignored. `makes_folder`: the command creates the file's
  // folder if need be (compare --plot DIR).
  void output(const std::string& option, const std::string& path, bool makes_folder = false);
  // Throws InputError naming the option and the file for the first that breaks the rules above.
  void check(bool overwrite) const;

 private:
  struct Output {
    std::string option, path;
    bool makes_folder;
  };
  std::vector<std::pair<std::string, std::string>> inputs_;
  std::vector<Output> outputs_;
};

}  // namespace rockdem
