// `rockdem describe NAME`: the parameters of a joint law, effect or rock material, each with its
// unit, default, allowed range and meaning, printed from the same declaration that checks case
// files (so the documentation cannot drift from the code).
#include <cstdio>
#include <string>
#include <vector>

#include "framework/app/command.hpp"
#include "framework/core/did_you_mean.hpp"
#include "framework/core/error.hpp"
#include "framework/plugin_api/joint_law.hpp"
#include "framework/plugin_api/rock_material.hpp"

namespace rockdem {
namespace {

template <class Entry>
void describe(const char* what, const Entry& e) {
  std::printf("%s %s: %s\n", what, e.name.c_str(), e.summary.c_str());
  if (!e.reference.empty()) std::printf("reference: %s\n", e.reference.c_str());
  std::printf("\nparameters (quantities are written with a unit, e.g. \"38 deg\"):\n");
  for (const auto& p : e.params) {
    std::string kind;
    if (p.kind == "real") {
      kind = p.dim == Dimension::dimensionless ? std::string("number")
                                               : std::string(dimension_name(p.dim)) + " in " + std::string(units_for(p.dim));
    } else {
      kind = p.kind;
    }
    std::printf("  %s  (%s)\n      default: %s   allowed: %s\n      %s\n", p.name.c_str(), kind.c_str(),
                p.default_display().c_str(), p.range_text().c_str(), p.doc.c_str());
  }
}

const CommandRegistrar reg{Command{
    "describe", "print the parameters of a joint law, effect or rock material (unit, default, range, meaning)", false,
    [](CLI::App& sub) {
      auto name = std::make_shared<std::string>();
      sub.add_option("name", *name, "law, effect or material name (see `rockdem laws`)")->required();
      return [name]() -> int {
        if (const auto* e = JointLawRegistry::instance().find(*name)) {
          describe("joint law", *e);
        } else if (const auto* f = EffectRegistry::instance().find(*name)) {
          describe("effect", *f);
        } else if (const auto* m = RockMaterialRegistry::instance().find(*name)) {
          describe("rock material", *m);
        } else {
          std::vector<std::string> all = JointLawRegistry::instance().names();
          for (const auto& n : EffectRegistry::instance().names()) all.push_back(n);
          for (const auto& n : RockMaterialRegistry::instance().names()) all.push_back(n);
          throw InputError("describe: unknown name '" + *name + "'" + did_you_mean(*name, all) + "; joint laws: " +
                           JointLawRegistry::instance().names_joined() +
                           "; effects: " + EffectRegistry::instance().names_joined() +
                           "; rock materials: " + RockMaterialRegistry::instance().names_joined());
        }
        return 0;
      };
    }}};

}  // namespace
}  // namespace rockdem
