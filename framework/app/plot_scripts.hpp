#pragma once
// The Python plot scripts of scripts/ that some subcommands call (compare --plot, diagnose
// --report), run by Debian's /usr/bin/python3: it has python3-matplotlib, while the first python3
// on PATH may be a virtual environment without it.
#include <filesystem>
#include <string>
#include <vector>

namespace rockdem {

// scripts/<name>: $<env_var> if set, else scripts/ in a folder above this binary (build/rockdem
// -> scripts/), else scripts/ under the current folder. Throws std::runtime_error, prefixed by
// `option` (e.g. "--plot"), listing the places looked in when none has it.
std::filesystem::path find_plot_script(const std::string& name, const char* env_var, const std::string& option);

// Runs /usr/bin/python3 with `args` (script first) and waits; returns its exit code (1 if it did
// not exit normally). Throws std::runtime_error, prefixed by `option`, if it cannot be started.
int run_debian_python(const std::vector<std::string>& args, const std::string& option);

}  // namespace rockdem
