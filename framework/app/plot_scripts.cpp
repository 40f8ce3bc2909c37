#include "framework/app/plot_scripts.hpp"

#include <spawn.h>
#include <sys/wait.h>

#include <cstdlib>
#include <stdexcept>

#include "rockdem_version.hpp"

extern char** environ;

namespace rockdem {

namespace fs = std::filesystem;

fs::path find_plot_script(const std::string& name, const char* env_var, const std::string& option) {
  if (const char* env = std::getenv(env_var); env && *env) return env;
  std::vector<fs::path> tried;
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    for (fs::path dir = exe.parent_path(); !dir.empty(); dir = dir.parent_path()) {
      // scripts/ beside a build in the source tree; share/rockdem/scripts/ of an installed one
      // (bin/rockdem, `cmake --install`).
      for (const fs::path& p : {dir / "scripts" / name, dir / "share" / "rockdem" / "scripts" / name}) {
        tried.push_back(p);
        if (fs::exists(p)) return p;
      }
      if (dir == dir.root_path()) break;
    }
  }
  // The source tree this binary was built from, for a build folder outside it.
  tried.push_back(fs::path(ROCKDEM_SOURCE_DIR) / "scripts" / name);
  if (fs::exists(tried.back())) return tried.back();
  tried.push_back(fs::current_path() / "scripts" / name);
  if (fs::exists(tried.back())) return tried.back();
  std::string where;
  for (const auto& t : tried) where += "\n  " + t.string();
  throw std::runtime_error(option + ": scripts/" + name + " not found (set " + env_var + "); looked in:" + where);
}

int run_debian_python(const std::vector<std::string>& args, const std::string& option) {
  std::vector<std::string> all{"/usr/bin/python3"};
  all.insert(all.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (auto& a : all) argv.push_back(a.data());
  argv.push_back(nullptr);
  pid_t pid = 0;
  if (posix_spawn(&pid, argv[0], nullptr, nullptr, argv.data(), environ) != 0)
    throw std::runtime_error(option + ": cannot start /usr/bin/python3 (Debian's python3 with python3-matplotlib)");
  int status = 0;
  if (waitpid(pid, &status, 0) < 0) throw std::runtime_error(option + ": lost the plot process");
  return WIFEXITED(status) ? WEXITSTATUS(status) : 1;
}

}  // namespace rockdem
