#pragma once
// Results the subcommands write (JSON summaries): never half-written (through a temporary file
// and a rename), and, where every number is a result (compare's errors), never with a NaN or inf
// in them (nlohmann would write it as null, and a reader would take it for "no value").
#include <nlohmann/json.hpp>
#include <string>

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
