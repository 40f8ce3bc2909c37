#pragma once
// The kinds of boundary condition a case can name (`type = "fixed"`, ...), registered by name each
// in its own file beside its class (fixed_condition.cpp, ...), with the keys it takes. A case
// reader asks this list which keys a kind has and how to read them, and the case builder makes a
// condition without knowing the kinds, so adding a kind touches no reader or builder.
// A kind is made from a neutral description (ConditionInput), not from a file format: readers
// fill it from their files, other code (e.g. a model generator) fills it directly.
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "framework/boundary/conditions.hpp"
#include "framework/core/registry.hpp"
#include "framework/core/units.hpp"
#include "framework/model/stress_field.hpp"

namespace rockdem {

// One key a kind takes: how a reader reads it, and what it means (for documentation).
struct ConditionKey {
  enum class Type {
    time_function,  // a value with unit or a time history, of `dimension`
    names,          // a list of names, e.g. components = ["x"]
    choice,         // one name, e.g. base = "compliant" (read into ConditionValue::names[0])
  };
  std::string name;
  Type type = Type::time_function;
  Dimension dimension = Dimension::dimensionless;
  std::string description;
};

// The value given for a key, with where it was written (for messages).
struct ConditionValue {
  std::optional<TimeFunction> function;  // time_function keys
  std::vector<std::string> names;        // names keys
  std::vector<std::string> name_wheres;  // where each of `names` was written
  std::string where;
};

// Everything a kind's factory needs: the block's face it acts on and the values of the keys given.
struct ConditionInput {
  const Model& model;
  FaceSelection selection;
  bool rigid = false;  // the selection's block is rigid
  std::map<std::string, ConditionValue> values;
  std::string where;  // the condition as a whole, for messages
  // The case's in-situ stress field ([in_situ]), or null when the case has none; kinds that load
  // a boundary with it (in_situ_condition.cpp) copy it.
  const StressField* stress_field = nullptr;
  // The selection is a block's share of a region (region.hpp), not a named face: a kind that
  // holds a component of a rigid block then also holds its spin when the region covers one of
  // its edges (a roller along a face lets no point of it move across, so the face cannot turn).
  bool by_region = false;
  const ConditionValue* value(const std::string& key) const;
  // The time function given for `key`, or none if the key was not given.
  std::optional<TimeFunction> function(const std::string& key) const;
};

struct ConditionKind {
  std::string name;
  std::string summary;
  std::vector<ConditionKey> keys;
  // Acts on a whole rigid block, so that naming a face of a rigid block is a mistake.
  bool whole_rigid_block = false;
  std::function<std::unique_ptr<BoundaryCondition>(const ConditionInput&)> make;
  // Kinds whose condition spans several blocks (a free-field column along a side made of many
  // blocks) make one condition from all the selections of a region (or the one of a block face);
  // `in.selection` is then the first of them. Empty: one condition per selection, by `make`.
  std::function<std::unique_ptr<BoundaryCondition>(const ConditionInput& in, const std::vector<FaceSelection>& all)>
      make_spanning;
};

// Kinds in the order of their ranks (the order messages and documentation list them in). Kinds
// register from several source files, whose static initialisation order is not defined, so each
// declares its place in the list rather than relying on when it registers.
class ConditionKinds : public NamedTable<ConditionKind> {
 public:
  static ConditionKinds& instance();
  // Throws an InputError at `where` listing the valid kinds when `name` is unknown.
  const ConditionKind& get(const std::string& name, const std::string& where) const {
    return NamedTable::get(name, "boundary type", where, "valid: ");
  }
  // The first kind's declaration of `key` (kinds that share a key read it alike), or null.
  const ConditionKey* key(const std::string& name) const;
  // The keys of all kinds, each once, in the order of the kinds.
  std::vector<std::string> key_names() const;
};

// Registers a kind at static initialisation, at its rank in the list of kinds:
// `const ConditionKindRegistrar r{rank, ConditionKind{...}};`
struct ConditionKindRegistrar {
  ConditionKindRegistrar(int rank, ConditionKind kind) { ConditionKinds::instance().add(std::move(kind), rank); }
};

}  // namespace rockdem
