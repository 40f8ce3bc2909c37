// `rockdem laws`: what the registries hold (joint laws, effects, rock materials), one line each
// with its summary and reference, so users see every model a case file may name.
#include <cstdio>

#include "framework/app/command.hpp"
#include "framework/plugin_api/joint_law.hpp"
#include "framework/plugin_api/rock_material.hpp"

namespace rockdem {
namespace {

template <class R>
void list(const char* title, const R& registry) {
  std::printf("%s:\n", title);
  if (registry.entries().empty()) std::printf("  (none registered)\n");
  for (const auto& [name, e] : registry.entries()) {
    std::printf("  %-24s %s\n", name.c_str(), e.summary.c_str());
    if (!e.reference.empty()) std::printf("  %-24s   ref: %s\n", "", e.reference.c_str());
  }
}

const CommandRegistrar reg{Command{"laws", "list the joint laws, effects and rock materials rockdem knows", false,
                                   [](CLI::App&) {
                                     return []() -> int {
                                       list("joint laws", JointLawRegistry::instance());
                                       list("effects (composed with a law: effects = [...])", EffectRegistry::instance());
                                       list("rock materials", RockMaterialRegistry::instance());
                                       std::printf("\n`rockdem describe NAME` prints the parameters of one of them.\n");
                                       return 0;
                                     };
                                   }}};

}  // namespace
}  // namespace rockdem
