#include "framework/app/cli_contract.hpp"

#include <iostream>
#include <string>
#include <vector>

#include "framework/core/did_you_mean.hpp"

namespace rockdem {
namespace {

std::vector<std::string> subcommand_names(const CLI::App& app) {
  std::vector<std::string> out;
  for (const CLI::App* s : app.get_subcommands([](const CLI::App*) { return true; })) out.push_back(s->get_name());
  return out;
}

CLI::App* find_subcommand(CLI::App& app, const std::string& name) {
  for (CLI::App* s : app.get_subcommands([](const CLI::App*) { return true; }))
    if (s->get_name() == name) return s;
  return nullptr;
}

// "--name" and "-n" spellings of every option of `app` (and the help flag).
std::vector<std::string> option_spellings(const CLI::App& app) {
  std::vector<std::string> out;
  for (const CLI::Option* o : app.get_options()) {
    for (const auto& l : o->get_lnames()) out.push_back("--" + l);
    for (const auto& s : o->get_snames()) out.push_back("-" + s);
  }
  return out;
}

std::string& stored_command_line() {
  static std::string s;
  return s;
}

}  // namespace

void set_command_line(int argc, char** argv) {
  std::string& s = stored_command_line();
  s.clear();
  for (int i = 0; i < argc; ++i) {
    const std::string a = argv[i];
    const bool plain = !a.empty() && a.find_first_of(" \t\"'\\$`") == std::string::npos;
    s += (i ? " " : "") + (plain ? a : "'" + a + "'");
  }
}

const std::string& command_line() { return stored_command_line(); }

std::optional<int> check_command_line(CLI::App& app, int argc, char** argv, bool print) {
  if (argc < 2) return std::nullopt;
  const std::string first = argv[1];
  if (first == "help") {
    CLI::App* sub = argc > 2 ? find_subcommand(app, argv[2]) : nullptr;
    if (print) std::cout << (sub ? sub->help() : app.help());
    if (argc > 2 && !sub) {
      if (print) std::cerr << "rockdem: unknown subcommand '" << argv[2] << "'" << did_you_mean(argv[2], subcommand_names(app)) << "\n";
      return 2;
    }
    return 0;
  }
  if (first.empty() || first.front() == '-' || find_subcommand(app, first)) return std::nullopt;
  if (print) {
    std::cerr << "rockdem: unknown subcommand '" << first << "'" << did_you_mean(first, subcommand_names(app))
              << "; valid subcommands: ";
    bool comma = false;
    for (const auto& n : subcommand_names(app)) {
      std::cerr << (comma ? ", " : "") << n;
      comma = true;
    }
    std::cerr << "\n\n" << app.help();
  }
  return 2;
}

int report_parse_error(CLI::App& app, const CLI::ParseError& e, int argc, char** argv, bool print) {
  if (dynamic_cast<const CLI::CallForHelp*>(&e) || dynamic_cast<const CLI::CallForAllHelp*>(&e) ||
      dynamic_cast<const CLI::CallForVersion*>(&e)) {
    return print ? app.exit(e) : 0;  // CLI11 prints the help or version; exit 0
  }
  if (!print) return 2;
  CLI::App* sub = argc > 1 ? find_subcommand(app, argv[1]) : nullptr;
  std::cerr << "rockdem" << (sub ? " " + sub->get_name() : std::string()) << ": " << e.what() << "\n";
  const std::vector<std::string> known = option_spellings(sub ? *sub : app);
  for (int i = sub ? 2 : 1; i < argc; ++i) {
    std::string token = argv[i];
    if (token.size() < 2 || token.front() != '-') continue;
    if (token == "--") break;
    token = token.substr(0, token.find('='));
    bool is_known = false;
    for (const auto& k : known) is_known = is_known || k == token;
    if (!is_known) std::cerr << "rockdem: unknown option '" << token << "'" << did_you_mean(token, known) << "\n";
  }
  std::cerr << "\n" << (sub ? sub->help() : app.help());
  return 2;
}

}  // namespace rockdem
