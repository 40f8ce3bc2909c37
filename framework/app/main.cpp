// rockdem: 2D block distinct-element code for jointed rock. Subcommands are registered in
// framework/app/cmd_*.cpp; this file only parses and dispatches, and turns errors into messages
// and non-zero exit codes.
#include <CLI/CLI.hpp>
#include <iostream>

#include "framework/app/command.hpp"
#include "framework/core/error.hpp"
#include "framework/parallel/mpi_env.hpp"
#include "rockdem_version.hpp"

int main(int argc, char** argv) {
  rockdem::MpiEnvironment mpi(argc, argv);
  CLI::App app{"rockdem: 2D block distinct-element method for jointed rock"};
  app.set_version_flag("--version", std::string("rockdem ") + ROCKDEM_VERSION);
  app.require_subcommand(1);
  std::function<int()> action;
  const int rank = mpi.rank();
  for (const auto& [name, cmd] : rockdem::CommandRegistry::instance().entries()) {
    CLI::App* sub = app.add_subcommand(name, cmd.summary);
    auto run = cmd.setup(*sub);
    const bool all = cmd.runs_on_all_ranks;
    sub->callback([&action, run, all, rank]() {
      // Serial commands run on rank 0; other ranks only join the final exit-code agreement.
      if (all || rank == 0) action = run;
    });
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return mpi.finish(code);
  }
  int code = 0;
  try {
    code = action ? action() : 0;
  } catch (const rockdem::InputError& e) {
    if (mpi.rank() == 0) std::cerr << "rockdem: input error: " << e.what() << "\n";
    code = 2;
  } catch (const rockdem::InstabilityError& e) {
    if (mpi.rank() == 0) std::cerr << "rockdem: run unstable: " << e.what() << "\n";
    code = 3;
  } catch (const std::exception& e) {
    if (mpi.rank() == 0) std::cerr << "rockdem: error: " << e.what() << "\n";
    code = 1;
  }
  return mpi.finish(code);
}
