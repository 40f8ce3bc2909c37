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

void ConditionKinds::add(int rank, ConditionKind kind) {
  const auto at = std::upper_bound(ranks_.begin(), ranks_.end(), rank);
  kinds_.insert(kinds_.begin() + (at - ranks_.begin()), std::move(kind));
  ranks_.insert(at, rank);
}

const ConditionKind* ConditionKinds::find(const std::string& name) const {
  for (const auto& k : kinds_)
    if (k.name == name) return &k;
  return nullptr;
}

const ConditionKind& ConditionKinds::get(const std::string& name, const std::string& where) const {
  if (const ConditionKind* k = find(name)) return *k;
  throw InputError(where + ": unknown boundary type '" + name + "'; valid: " + join_names(kinds_, &ConditionKind::name));
}

const ConditionKey* ConditionKinds::key(const std::string& name) const {
  for (const auto& k : kinds_)
    for (const auto& key : k.keys)
      if (key.name == name) return &key;
  return nullptr;
}

std::vector<std::string> ConditionKinds::key_names() const {
  std::vector<std::string> out;
  for (const auto& k : kinds_)
    for (const auto& key : k.keys)
      if (std::find(out.begin(), out.end(), key.name) == out.end()) out.push_back(key.name);
  return out;
}

}  // namespace rockdem
