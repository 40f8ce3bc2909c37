#pragma once
// Lists of names in messages ("...; valid: a, b, c"): one spelling of the list for every message
// that tells the user what is valid, so that they all read alike.
#include <functional>
#include <string>
#include <string_view>

namespace rockdem {

// The names in `range` joined by ", " in the range's order. `name_of` turns an element into its
// name (e.g. the key of a map entry, or a member); by default the element is the name.
template <class Range, class NameOf = std::identity>
std::string join_names(const Range& range, NameOf name_of = {}) {
  std::string out;
  for (const auto& element : range) {
    if (!out.empty()) out += ", ";
    out += std::string_view(std::invoke(name_of, element));
  }
  return out;
}

// The keys of a map (or any range of pairs) joined as by join_names.
template <class Map>
std::string join_keys(const Map& map) {
  return join_names(map, [](const auto& entry) -> const auto& { return entry.first; });
}

}  // namespace rockdem
