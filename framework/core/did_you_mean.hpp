#pragma once
// "did you mean ...?" for unknown names (subcommands, options, case keys, law/effect/parameter
// names): the nearest valid name by edit distance, offered only when it is close enough to be a
// likely typo, so that a message never suggests an unrelated name.
#include <algorithm>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

namespace rockdem {

// Levenshtein distance (insertions, deletions, substitutions), case-sensitive.
inline size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<size_t> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    size_t diag = row[0];
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diag = up;
    }
  }
  return row[b.size()];
}

// The element of `range` whose name is nearest to `name`, or "" when none is within a third of
// the longer name's length (at least 1, at most 3 edits): "runn" -> "run", "kn_" -> "kn", but
// "blocks" suggests nothing among {"element", "compare"}.
template <class Range, class NameOf = std::identity>
std::string nearest_name(std::string_view name, const Range& range, NameOf name_of = {}) {
  std::string best;
  size_t best_d = static_cast<size_t>(-1);
  for (const auto& element : range) {
    const std::string_view candidate(std::invoke(name_of, element));
    const size_t d = edit_distance(name, candidate);
    const size_t limit = std::clamp<size_t>(std::max(name.size(), candidate.size()) / 3, 1, 3);
    if (d <= limit && d < best_d) {
      best_d = d;
      best = std::string(candidate);
    }
  }
  return best;
}

// " (did you mean 'x'?)" for the nearest name, or "" when none is close.
template <class Range, class NameOf = std::identity>
std::string did_you_mean(std::string_view name, const Range& range, NameOf name_of = {}) {
  const std::string best = nearest_name(name, range, name_of);
  return best.empty() ? std::string() : " (did you mean '" + best + "'?)";
}

}  // namespace rockdem
