#include "framework/app/result_files.hpp"

#include <cmath>
#include <filesystem>

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

namespace rockdem {

namespace {
namespace fs = std::filesystem;

// Whether two names are the same file, by what the file system says when both exist and by
// their normalised paths when one does not yet.
bool same_file(const std::string& a, const std::string& b) {
  std::error_code ec;
  if (fs::exists(a, ec) && fs::exists(b, ec)) return fs::equivalent(a, b, ec);
  return fs::weakly_canonical(a, ec) == fs::weakly_canonical(b, ec);
}
}  // namespace

void ResultFilePlan::input(const std::string& option, const std::string& path) {
  if (!path.empty()) inputs_.emplace_back(option, path);
}

void ResultFilePlan::output(const std::string& option, const std::string& path, bool makes_folder) {
  if (!path.empty()) outputs_.push_back({option, path, makes_folder});
}

void ResultFilePlan::check(bool overwrite) const {
  std::error_code ec;
  // A missing input is the first thing to hear of, before anything about the outputs.
  for (const auto& [option, path] : inputs_)
    if (!fs::exists(path, ec)) throw InputError(option + " " + path + ": no such file");
  for (std::size_t k = 0; k < outputs_.size(); ++k) {
    const auto& [option, path, makes_folder] = outputs_[k];
    const std::string what = option + " " + path;
    for (const auto& [in_option, in_path] : inputs_)
      if (same_file(path, in_path))
        throw InputError(what + ": this is " + in_option + ", an input; writing the result would replace it "
                         "(even with --overwrite); give the result another name");
    for (std::size_t j = 0; j < k; ++j)
      if (same_file(path, outputs_[j].path))
        throw InputError(what + ": " + outputs_[j].option + " writes the same file; give each result its own name");
    if (fs::is_directory(path, ec)) throw InputError(what + ": is a folder; give a file name");
    // A result is written beside its name and renamed onto it: what stands there must be a plain
    // file (a link, a device or a pipe would be replaced by the result, not written through).
    const fs::file_status st = fs::symlink_status(path, ec);
    if (fs::exists(st) && !fs::is_regular_file(st))
      throw InputError(what + ": exists and is not a plain file (" +
                       (fs::is_symlink(st) ? "a symbolic link" : "a device, pipe or socket") +
                       "); give the name of a new or plain file");
    fs::path parent = fs::path(path).parent_path();
    // The nearest part of the path that exists must be a folder (compare --plot DIR makes DIR).
    if (makes_folder)
      while (!parent.empty() && !fs::exists(parent, ec) && parent.has_parent_path() && parent.parent_path() != parent)
        parent = parent.parent_path();
    if (!parent.empty() && fs::exists(parent, ec) && !fs::is_directory(parent, ec))
      throw InputError(what + ": '" + parent.string() + "' is a file, not a folder");
    if (!makes_folder && !parent.empty() && !fs::is_directory(parent, ec))
      throw InputError(what + ": the folder '" + parent.string() + "' does not exist (create it first)");
    if (fs::exists(path, ec) && !overwrite)
      throw InputError(what + ": the file exists (an earlier result?); add --overwrite to replace it, or give another name");
  }
}

}  // namespace rockdem
