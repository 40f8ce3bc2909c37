#pragma once
// Subcommands of `rockdem` (git style). Each subcommand lives in its own file in framework/app/
// and registers itself; main() only dispatches.
#include <CLI/CLI.hpp>
#include <functional>
#include <string>

#include "framework/core/registry.hpp"

namespace rockdem {

struct Command {
  std::string name;
  std::string summary;
  // false: only rank 0 runs it under mpirun; the other ranks wait for it to finish.
  bool runs_on_all_ranks = false;
  // Adds options to `sub` and returns the action to run once parsed (exit code).
  std::function<std::function<int()>(CLI::App& sub)> setup;
};

// Subcommands by name, listed alphabetically.
class CommandRegistry : public NamedTable<Command> {
 public:
  static CommandRegistry& instance() {
    static CommandRegistry r;
    return r;
  }
};

struct CommandRegistrar {
  explicit CommandRegistrar(Command c) { CommandRegistry::instance().add(std::move(c)); }
};

}  // namespace rockdem
