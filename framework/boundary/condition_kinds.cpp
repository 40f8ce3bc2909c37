#include "framework/boundary/condition_kinds.hpp"

#include <algorithm>

#include "framework/core/error.hpp"
#include "framework/core/names.hpp"

namespace rockdem {

const ConditionValue* ConditionInput::value(const std::string& key) const {
  auto it = values.find(key);
  return it == values.end() ? nullptr : &it->second;
}

std::optional<TimeFunction> ConditionInput::function(const std::string& key) const {
  const ConditionValue* v = value(key);
  return v ? v->function : std::nullopt;
}

ConditionKinds& ConditionKinds::instance() {
  static ConditionKinds kinds;
  return kinds;
}

const ConditionKey* ConditionKinds::key(const std::string& name) const {
  for (const auto& [kind_name, kind] : entries())
    for (const auto& key : kind.keys)
      if (key.name == name) return &key;
  return nullptr;
}

std::vector<std::string> ConditionKinds::key_names() const {
  std::vector<std::string> out;
  for (const auto& [kind_name, kind] : entries())
    for (const auto& key : kind.keys)
      if (std::find(out.begin(), out.end(), key.name) == out.end()) out.push_back(key.name);
  return out;
}

}  // namespace rockdem
