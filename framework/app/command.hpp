#pragma once
// Subcommands of `rockdem` (git style). Each subcommand lives in its own file in framework/app/
// and registers itself; main() only dispatches.
#include <CLI/CLI.hpp>
#include <functional>
#include <map>
#include <string>

namespace rockdem {

struct Command {
  std::string name;
  std::string summary;
  // false: only rank 0 runs it under mpirun; the other ranks wait for it to finish.
  bool runs_on_all_ranks = false;
  // Adds options to `sub` and returns the action to run once parsed (exit code).
  std::function<std::function<int()>(CLI::App& sub)> setup;
};

class CommandRegistry {
 public:
  static CommandRegistry& instance() {
    static CommandRegistry r;
    return r;
  }
  void add(Command c) { commands_[c.name] = std::move(c); }
  const std::map<std::string, Command>& commands() const { return commands_; }

 private:
  std::map<std::string, Command> commands_;
};

struct CommandRegistrar {
  explicit CommandRegistrar(Command c) { CommandRegistry::instance().add(std::move(c)); }
};

}  // namespace rockdem
