#pragma once
// Output folders that never mix two runs, and the manifest that says what made a folder.
//
// A run writes into an empty or new folder. A non-empty one is refused unless the user asks for
// --overwrite, and even then only a folder with a rockdem manifest.json is emptied: a folder
// without one may hold the user's own files. A restart (--restart) continues the run whose folder
// it is, so it may write into a non-empty folder, again only one with a manifest.
//
// manifest.json records the case (copied in beside it as case.toml), the rockdem version and
// commit, the command line, start and end times (UTC), the stage names and the exit status.
// It is written when the run starts (status "running") and again when it ends, each time to a
// temporary file that is renamed, so a killed run leaves a readable manifest saying "running".
#include <filesystem>
#include <string>
#include <vector>

namespace rockdem {

enum class FolderUse { fresh, overwrite, resume };

// Makes `dir` ready for a run (creates it when missing) or throws an InputError naming `option`,
// the folder and what to do instead. `kind` is what is about to write the folder (Manifest::kind):
// --overwrite and --resume accept only a folder whose manifest says the same kind, so that a
// diagnosis report never empties a run's folder or the other way round.
void prepare_output_folder(const std::filesystem::path& dir, FolderUse use, const std::string& option,
                           const std::string& kind = "run");

struct Manifest {
  std::string kind = "run";  // what wrote the folder: "run" (rockdem run) or "diagnose report"
  std::string command_line;
  std::string case_file;  // as given ("" for a built-in case)
  std::string case_text;  // copied into the folder as case.toml ("" when unknown)
  std::vector<std::string> stages;
  std::string restart;  // checkpoint a restart continued from
  std::string started_utc, ended_utc;
  std::string status = "running";  // "running", "finished", "unstable", "interrupted", "failed"
  int exit_code = -1;              // -1 while running
};

// Writes <dir>/manifest.json (and <dir>/case.toml when case_text is set) by temporary file and
// rename. Throws std::runtime_error naming the path when the disk is full or the folder unwritable.
void write_manifest(const std::filesystem::path& dir, const Manifest& m);

// Records the end of what wrote the folder (end time, status, exit code) in `m` and writes it.
void close_manifest(const std::filesystem::path& dir, Manifest& m, const std::string& status, int exit_code);

// Copies the manifest into root attributes of an HDF5 file written by this run (rockdem_version,
// rockdem_commit, command_line, case_file, stages, started_utc, ended_utc, status, exit_code).
void stamp_hdf5(const std::filesystem::path& h5_file, const Manifest& m);

// The current time as an ISO 8601 UTC string, e.g. "2026-11-23T21:05:00Z".
std::string utc_now();

// Writes `text` to `path` through `path`.tmp and a rename, so that a reader (or a killed run)
// sees the old file or the complete new one, never half of one. Throws std::runtime_error naming
// the path on a write failure (disk full, no permission) and removes the temporary file.
void write_file_atomically(const std::filesystem::path& path, const std::string& text);

}  // namespace rockdem
