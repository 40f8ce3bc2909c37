#include "framework/app/result_files.hpp"

#include <cmath>

#include "framework/core/error.hpp"
#include "framework/io/output_folder.hpp"

namespace rockdem {

std::string first_nonfinite(const nlohmann::json& j, const std::string& at) {
  if (j.is_number_float()) return std::isfinite(j.get<double>()) ? "" : (at.empty() ? "/" : at);
  if (j.is_object()) {
    for (auto it = j.begin(); it != j.end(); ++it)
      if (auto p = first_nonfinite(it.value(), at + "/" + it.key()); !p.empty()) return p;
  } else if (j.is_array()) {
    for (std::size_t i = 0; i < j.size(); ++i)
      if (auto p = first_nonfinite(j[i], at + "/" + std::to_string(i)); !p.empty()) return p;
  }
  return "";
}

void require_finite_result(const nlohmann::json& j, const std::string& inputs) {
  const std::string p = first_nonfinite(j);
  if (p.empty()) return;
  throw InputError(inputs + ": the result is not finite (" + p + " = " + std::to_string(j.at(nlohmann::json::json_pointer(p == "/" ? "" : p)).get<double>()) +
                   "): a value in the input is too large or not a number; nothing was written. Valid: finite values "
                   "whose squares and sums stay finite (well below 1e150 in the input's units)");
}

void write_json_result(const std::string& path, const nlohmann::json& j) { write_file_atomically(path, j.dump(2) + "\n"); }

}  // namespace rockdem
