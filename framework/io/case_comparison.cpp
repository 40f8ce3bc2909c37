#include "framework/io/case_comparison.hpp"

#include <algorithm>
#include <charconv>
#include <map>
#include <set>
#include <sstream>

#include <toml++/toml.h>

#include "framework/core/error.hpp"

namespace rockdem {
namespace {

std::set<std::string> names_in(const toml::node* n) {
  std::set<std::string> out;
  if (!n) return out;
  if (const auto* s = n->as_string()) out.insert(s->get());
  if (const auto* a = n->as_array())
    for (const auto& e : *a)
      if (const auto* s = e.as_string()) out.insert(s->get());
  return out;
}

// Keeps only what the first `completed` stages ran with (see the header).
void keep_completed_part(toml::table& t, std::size_t completed) {
  std::set<std::string> done, played;
  if (auto* st = t["stages"].as_array()) {
    while (st->size() > completed) st->erase(st->end() - 1);
    for (const auto& e : *st)
      if (const auto* s = e.as_table()) {
        if (const auto* n = s->get_as<std::string>("name")) done.insert(n->get());
        for (const auto& m : names_in(s->get("motion"))) played.insert(m);
      }
  }
  if (auto* bc = t["boundary"].as_array())
    for (auto& e : *bc) {
      auto* b = e.as_table();
      if (!b || names_in(b->get("stages")).empty()) continue;  // active in every stage (no or an empty list)
      toml::array active;
      for (const auto& n : names_in(b->get("stages")))
        if (done.count(n)) active.push_back(n);
      if (active.empty()) b->clear();  // active only in stages still to run
      else b->insert_or_assign("stages", std::move(active));
    }
  if (auto* mo = t["motions"].as_array()) {
    toml::array used;
    for (const auto& e : *mo) {
      const auto* m = e.as_table();
      const auto* n = m ? m->get_as<std::string>("name") : nullptr;
      if (n && played.count(n->get())) used.push_back(*m);
    }
    if (used.empty()) t.erase("motions");  // none played yet: as if the case had none
    else *mo = std::move(used);
  }
  // When and how many checkpoints a run writes does not change what it computes.
  if (auto* out = t["output"].as_table())
    for (const char* k : {"checkpoint_every", "checkpoint_keep", "progress_seconds"}) out->erase(k);
  if (auto* ds = t["direct_shear"].as_table()) {
    auto* shear = (*ds)["shear_stages"].as_array();
    auto* stress = (*ds)["normal_stresses"].as_array();
    if (shear) {
      std::size_t k = 0;
      while (k < shear->size() && (*shear)[k].as_string() && done.count((*shear)[k].as_string()->get())) ++k;
      while (shear->size() > k) shear->erase(shear->end() - 1);
      if (stress)
        while (stress->size() > k) stress->erase(stress->end() - 1);
    }
  }
}

// One "key = value" line per value: tables joined with '.', entries of arrays of tables numbered.
void flatten(const toml::table& t, const std::string& prefix, std::vector<std::pair<std::string, std::string>>& out) {
  for (const auto& [k, node] : t) {
    const std::string key = prefix + std::string(k.str());
    if (const auto* sub = node.as_table()) {
      flatten(*sub, key + ".", out);
    } else if (const auto* arr = node.as_array(); arr && !arr->empty() && arr->is_array_of_tables()) {
      for (std::size_t i = 0; i < arr->size(); ++i) flatten(*arr->get(i)->as_table(), key + "[" + std::to_string(i) + "].", out);
    } else {
      std::string value;
      if (const auto* d = node.as_floating_point()) {
        char buf[32];  // the shortest text that reads back to the same double: 1e-07, not 9.99...95e-08
        value.assign(buf, std::to_chars(buf, buf + sizeof buf, d->get()).ptr);
      } else {
        std::ostringstream os;
        node.visit([&](const auto& v) { os << v; });
        value = os.str();
      }
      std::replace(value.begin(), value.end(), '\n', ' ');  // a long array printed over several lines
      out.emplace_back(key, value);
    }
  }
}

std::vector<std::pair<std::string, std::string>> completed_part(const std::string& text, std::size_t completed) {
  toml::table t;
  try {
    t = toml::parse(std::string_view(text), std::string_view("the case"));
  } catch (const toml::parse_error& e) {
    throw InputError(std::string("the case text it holds cannot be read (") + std::string(e.description()) + ")");
  }
  keep_completed_part(t, completed);
  std::vector<std::pair<std::string, std::string>> out;
  flatten(t, "", out);
  return out;
}

}  // namespace

std::vector<std::string> restart_differences(const std::string& before, const std::string& now, std::size_t completed) {
  const auto a = completed_part(before, completed), b = completed_part(now, completed);
  const std::map<std::string, std::string> in_a(a.begin(), a.end()), in_b(b.begin(), b.end());
  std::vector<std::string> diffs;
  for (const auto& [k, v] : a) {
    const auto w = in_b.find(k);
    if (w == in_b.end()) diffs.push_back(k + ": " + v + " in the checkpoint's case, absent from this one");
    else if (w->second != v) diffs.push_back(k + ": " + v + " in the checkpoint's case, " + w->second + " in this one");
  }
  for (const auto& [k, v] : b)
    if (!in_a.count(k)) diffs.push_back(k + ": " + v + " in this case, absent from the checkpoint's");
  return diffs;
}

}  // namespace rockdem
