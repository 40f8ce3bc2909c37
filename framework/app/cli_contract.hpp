#pragma once
// The command-line contract of `rockdem` (README, "Exit codes"): usage errors are exit 2 with
// the usage and a did-you-mean, help and --version are exit 0, and CLI11's own exit codes
// (106 "A subcommand is required", 109 extras, ...) never reach the user.
#include <CLI/CLI.hpp>
#include <optional>
#include <string>

namespace rockdem {

// Handles what must be decided before CLI11 parses: `rockdem help [SUBCOMMAND]` (usage, exit 0)
// and an unknown first word ("unknown subcommand 'runn' (did you mean 'run'?)", exit 2). Returns
// the exit code when the command line is fully handled, nullopt to go on parsing. Prints only
// when `print` (rank 0 under MPI).
std::optional<int> check_command_line(CLI::App& app, int argc, char** argv, bool print);

// Turns a CLI11 parse error into the contract: help/version exit 0 as CLI11 prints them; every
// other error prints the message, a did-you-mean for each unknown option, and the usage of the
// subcommand; returns 2.
int report_parse_error(CLI::App& app, const CLI::ParseError& e, int argc, char** argv, bool print);

// The command line as typed (arguments quoted where needed), for output manifests; set by main().
void set_command_line(int argc, char** argv);
const std::string& command_line();

}  // namespace rockdem
