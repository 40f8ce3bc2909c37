#include "framework/io/output_folder.hpp"

#include <hdf5.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <stdexcept>

#include "framework/core/error.hpp"
#include "framework/io/hdf5_util.hpp"
#include "rockdem_version.hpp"

namespace rockdem {
namespace fs = std::filesystem;
namespace {

std::string json_string(const std::string& s) {
  std::string out = "\"";
  for (const unsigned char c : s) {
    switch (c) {
      case '"': out += "\\\""; break;
      case '\\': out += "\\\\"; break;
      case '\n': out += "\\n"; break;
      case '\t': out += "\\t"; break;
      case '\r': out += "\\r"; break;
      default:
        if (c < 0x20) {
          char buf[8];
          std::snprintf(buf, sizeof buf, "\\u%04x", c);
          out += buf;
        } else {
          out += static_cast<char>(c);
        }
    }
  }
  return out + "\"";
}

std::string joined_stages(const Manifest& m) {
  std::string s;
  for (const auto& n : m.stages) s += (s.empty() ? "" : ", ") + n;
  return s;
}

}  // namespace

namespace {
// The kind of the folder's manifest.json ("run" for manifests written before kinds were recorded;
// "" when it cannot be read as a manifest).
std::string manifest_kind(const fs::path& file) {
  std::ifstream in(file);
  try {
    const nlohmann::json j = nlohmann::json::parse(in);
    if (!j.is_object() || j.value("format", "") != "rockdem-manifest") return "";
    return j.value("kind", "run");
  } catch (const nlohmann::json::exception&) {
    return "";
  }
}
}  // namespace

void prepare_output_folder(const fs::path& dir, FolderUse use, const std::string& option, const std::string& kind) {
  std::error_code ec;
  if (!fs::exists(dir, ec)) {
    fs::create_directories(dir, ec);
    if (ec) throw InputError(option + " " + dir.string() + ": cannot create the folder: " + ec.message());
    return;
  }
  if (!fs::is_directory(dir, ec)) throw InputError(option + " " + dir.string() + ": exists and is not a folder");
  auto it = fs::directory_iterator(dir, ec);
  if (ec) throw InputError(option + " " + dir.string() + ": cannot read the folder: " + ec.message());
  if (it == fs::directory_iterator()) return;  // empty
  const bool ours = fs::exists(dir / "manifest.json");
  const std::string example = it->path().filename().string();
  if (ours && use != FolderUse::fresh) {
    const std::string found = manifest_kind(dir / "manifest.json");
    if (found != kind)
      throw InputError(option + " " + dir.string() + ": this folder holds " +
                       (found.empty() ? std::string("a manifest.json rockdem cannot read") : "a rockdem " + found) +
                       ", not a " + kind + " (its manifest.json says so); " +
                       (use == FolderUse::resume ? "a restart continues only its own run's folder"
                                                 : "--overwrite empties only a folder an earlier " + kind + " wrote") +
                       ": give another folder");
  }
  if (use == FolderUse::resume) {
    if (!ours)
      throw InputError(option + " " + dir.string() + ": a restart writes into the folder of the run it continues (one with a "
                       "manifest.json) or into an empty one; this folder holds other files (e.g. '" + example + "')");
    return;
  }
  if (use == FolderUse::fresh) {
    throw InputError(option + " " + dir.string() + ": the folder is not empty (e.g. '" + example + "'); a " + kind + " never mixes "
                     "its files with another's: give a new or empty folder, or add --overwrite to empty this one first" +
                     (ours ? std::string() : " (only a folder rockdem wrote, with a manifest.json, is emptied)"));
  }
  if (!ours)
    throw InputError(option + " " + dir.string() + ": --overwrite empties only a folder rockdem wrote (one with a "
                     "manifest.json); this one has none and may hold your own files (e.g. '" + example + "'): "
                     "empty it yourself or give another folder");
  for (const auto& entry : fs::directory_iterator(dir)) fs::remove_all(entry.path());
}

std::string utc_now() {
  const std::time_t t = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  std::tm tm{};
  gmtime_r(&t, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}

void write_file_atomically(const fs::path& path, const std::string& text) {
  const fs::path tmp = path.string() + ".tmp";
  std::FILE* fp = std::fopen(tmp.c_str(), "wb");
  if (!fp) throw std::runtime_error("cannot write " + path.string() + ": cannot open " + tmp.string());
  const bool wrote = std::fwrite(text.data(), 1, text.size(), fp) == text.size();
  const bool closed = std::fclose(fp) == 0;
  std::error_code ec;
  if (!wrote || !closed) {
    fs::remove(tmp, ec);
    throw std::runtime_error("cannot write " + path.string() + " (disk full or no permission?)");
  }
  fs::rename(tmp, path, ec);
  if (ec) {
    fs::remove(tmp, ec);
    throw std::runtime_error("cannot write " + path.string() + ": rename failed");
  }
}

void write_manifest(const fs::path& dir, const Manifest& m) {
  if (!m.case_text.empty()) write_file_atomically(dir / "case.toml", m.case_text);
  std::string s = "{\n";
  s += "  \"format\": \"rockdem-manifest\",\n";
  s += "  \"kind\": " + json_string(m.kind) + ",\n";
  s += "  \"rockdem_version\": " + json_string(ROCKDEM_VERSION) + ",\n";
  s += "  \"rockdem_commit\": " + json_string(ROCKDEM_GIT_COMMIT) + ",\n";
  s += "  \"command_line\": " + json_string(m.command_line) + ",\n";
  s += "  \"case_file\": " + json_string(m.case_file) + ",\n";
  s += "  \"case_copy\": " + json_string(m.case_text.empty() ? "" : "case.toml") + ",\n";
  s += "  \"restart_from\": " + json_string(m.restart) + ",\n";
  s += "  \"stages\": [";
  for (std::size_t i = 0; i < m.stages.size(); ++i) s += (i ? ", " : "") + json_string(m.stages[i]);
  s += "],\n";
  s += "  \"started_utc\": " + json_string(m.started_utc) + ",\n";
  s += "  \"ended_utc\": " + (m.ended_utc.empty() ? std::string("null") : json_string(m.ended_utc)) + ",\n";
  s += "  \"status\": " + json_string(m.status) + ",\n";
  s += "  \"exit_code\": " + (m.exit_code < 0 ? std::string("null") : std::to_string(m.exit_code)) + "\n";
  s += "}\n";
  write_file_atomically(dir / "manifest.json", s);
}

void close_manifest(const fs::path& dir, Manifest& m, const std::string& status, int exit_code) {
  m.ended_utc = utc_now();
  m.status = status;
  m.exit_code = exit_code;
  write_manifest(dir, m);
}

void stamp_hdf5(const fs::path& h5_file, const Manifest& m) {
  const std::string path = h5_file.string();
  h5::QuietErrors quiet;
  h5::Handle fapl(h5::check(H5Pcreate(H5P_FILE_ACCESS), "file access properties"), H5Pclose);
  H5Pset_file_locking(fapl, false, true);
  h5::Handle file(H5Fopen(path.c_str(), H5F_ACC_RDWR, fapl), H5Fclose);
  if (!file.valid()) throw std::runtime_error("cannot open " + path + " to record the manifest in it");
  auto put = [&](const std::string& name, const std::string& value) {
    if (H5Aexists(file, name.c_str()) > 0) H5Adelete(file, name.c_str());
    h5::write_attr_string(file, name, value, path);
  };
  put("rockdem_version", ROCKDEM_VERSION);
  put("rockdem_commit", ROCKDEM_GIT_COMMIT);
  put("command_line", m.command_line);
  put("case_file", m.case_file);
  put("restart_from", m.restart);
  put("stages", joined_stages(m));
  put("started_utc", m.started_utc);
  put("ended_utc", m.ended_utc);
  put("status", m.status);
  if (H5Aexists(file, "exit_code") > 0) H5Adelete(file, "exit_code");
  h5::write_attr<std::int32_t>(file, "exit_code", m.exit_code, path);
}

}  // namespace rockdem
