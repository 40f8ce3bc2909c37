// rockdem: 2D block distinct-element code for jointed rock. Subcommands are registered in
// framework/app/cmd_*.cpp; this file only parses and dispatches, and turns errors into messages
// and non-zero exit codes.
#include <CLI/CLI.hpp>
#include <filesystem>
#include <iostream>
#include <new>

#include "framework/app/command.hpp"
#include "framework/app/cli_contract.hpp"
#include "framework/core/error.hpp"
#include "framework/core/interrupt.hpp"
#include "framework/io/library_setup.hpp"
#include "framework/parallel/mpi_env.hpp"
#include "rockdem_version.hpp"

int main(int argc, char** argv) {
  rockdem::quiet_io_libraries();
  rockdem::MpiEnvironment mpi(argc, argv);
  CLI::App app{"rockdem: 2D block distinct-element method for jointed rock"};
  app.set_version_flag("--version", std::string("rockdem ") + ROCKDEM_VERSION);
  app.require_subcommand(0, 1);
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
  // The exit-code contract (README): 0, 1, 2, 3, 130, 143 only; CLI11's own codes (106, 109...)
  // never reach the user, and a mistyped subcommand or option gets a did-you-mean.
  rockdem::set_command_line(argc, argv);
  if (const auto early = rockdem::check_command_line(app, argc, argv, mpi.rank() == 0)) return mpi.finish(*early);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return mpi.finish(rockdem::report_parse_error(app, e, argc, argv, mpi.rank() == 0));
  }
  if (!action && app.get_subcommands().empty()) {
    if (mpi.rank() == 0) std::cerr << "rockdem: a subcommand is required\n\n" << app.help();
    return mpi.finish(2);
  }
  int code = 0;
  const std::string sub = app.get_subcommands().empty() ? std::string() : app.get_subcommands().front()->get_name();
  try {
    code = action ? action() : 0;
  } catch (const rockdem::Interrupted& e) {
    if (mpi.rank() == 0) std::cerr << "rockdem: " << e.what() << "\n";
    code = e.exit_code();
  } catch (const rockdem::InputError& e) {
    if (mpi.rank() == 0) std::cerr << "rockdem: input error: " << e.what() << "\n";
    code = 2;
  } catch (const rockdem::InstabilityError& e) {
    if (mpi.rank() == 0) std::cerr << "rockdem: run unstable: " << e.what() << "\n";
    code = 3;
  } catch (const std::bad_alloc&) {
    if (mpi.rank() == 0)
      std::cerr << "rockdem " << sub << ": error: out of memory (std::bad_alloc): the input asks for more memory "
                << "than this machine has; check sizes, step lengths and counts in the input\n";
    code = 1;
  } catch (const std::filesystem::filesystem_error& e) {
    if (mpi.rank() == 0)
      std::cerr << "rockdem " << sub << ": error: file system: " << e.code().message() << ": '" << e.path1().string()
                << "'" << (e.path2().empty() ? std::string() : " and '" + e.path2().string() + "'") << "\n";
    code = 1;
  } catch (const std::exception& e) {
    if (mpi.rank() == 0) std::cerr << "rockdem " << sub << ": error: " << e.what() << "\n";
    code = 1;
  } catch (...) {
    if (mpi.rank() == 0) std::cerr << "rockdem " << sub << ": error: unexpected internal error\n";
    code = 1;
  }
  // Codes a command returns itself are mapped into the contract too (anything else is an error).
  if (code != 0 && code != 1 && code != 2 && code != 3 && code != 130 && code != 143) code = 1;
  return mpi.finish(code);
}
