#pragma once
// One table of a case file being read by key (the readers of [rock_mass] and [[motions]]): its
// file, its key path, and typed access that names "file:line key 'path.key'" in every message.
#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include <toml++/toml.h>

#include "framework/core/error.hpp"
#include "framework/core/names.hpp"
#include "framework/core/types.hpp"
#include "framework/core/units.hpp"
#include "framework/geometry/polygon.hpp"
#include "framework/io/toml_values.hpp"

namespace rockdem {

struct TomlTable {
  const toml::table& t;
  const std::string& file;
  std::string path;

  std::string key_at(const toml::node& n, const std::string& key) const {
    return toml_where(n, file) + " key '" + path + "." + key + "'";
  }
  std::string here() const { return toml_where(t, file) + " [" + path + "]"; }

  void only(std::initializer_list<std::string_view> keys) const {
    for (auto&& [k, v] : t)
      if (std::find(keys.begin(), keys.end(), k.str()) == keys.end())
        throw InputError(key_at(v, std::string(k.str())) + ": unknown key in [" + path + "]; valid keys: " + join_names(keys));
  }
  const toml::node& required(const std::string& key) const {
    if (const toml::node* n = t.get(key)) return *n;
    throw InputError(here() + ": missing required key '" + key + "'");
  }
  double value(const toml::node& n, const std::string& key, Dimension d) const {
    return quantity_value(raw_value(n, file, path + "." + key), d, "value");
  }
  std::optional<double> maybe(const std::string& key, Dimension d) const {
    const toml::node* n = t.get(key);
    return n ? std::optional<double>(value(*n, key, d)) : std::nullopt;
  }
  // A value that must be > 0 (or >= 0 if `zero_ok`); `def` if the key is absent.
  double at_least(const std::string& key, Dimension d, std::optional<double> def, bool zero_ok = false) const {
    const toml::node* n = t.get(key);
    if (!n && def) return *def;
    const double v = value(n ? *n : required(key), key, d);
    if (!(zero_ok ? v >= 0.0 : v > 0.0) || !std::isfinite(v))
      throw InputError(key_at(*n, key) + ": must be " + (zero_ok ? ">= 0" : "> 0") + ", got " + format_quantity(v, d));
    return v;
  }
  std::string text(const std::string& key, std::optional<std::string> def = std::nullopt) const {
    const toml::node* n = t.get(key);
    if (!n && def) return *def;
    if (const auto* s = (n ? n : &required(key))->as_string()) return s->get();
    throw InputError(key_at(*n, key) + ": expected a string");
  }
  bool flag(const std::string& key, bool def) const {
    const toml::node* n = t.get(key);
    if (!n) return def;
    if (const auto* b = n->as_boolean()) return b->get();
    throw InputError(key_at(*n, key) + ": expected true or false");
  }
  Vec2 point(const toml::node& n, const std::string& key) const {
    const auto* a = n.as_array();
    if (!a || a->size() != 2) throw InputError(key_at(n, key) + ": expected a point [x, y] with units, e.g. [\"0 m\", \"2 m\"]");
    return {value(*a->get(0), key, Dimension::length), value(*a->get(1), key, Dimension::length)};
  }
  Vec2 point(const std::string& key) const { return point(required(key), key); }
  // rectangle = [x0, y0, width, height] or polygon = [[x, y], ...], as in [[blocks]].
  Polygon shape(const std::string& what) const {
    if (const toml::node* n = t.get("rectangle")) {
      const auto* a = n->as_array();
      if (!a || a->size() != 4) throw InputError(key_at(*n, "rectangle") + ": expected [x0, y0, width, height] with units");
      double v[4];
      for (std::size_t i = 0; i < 4; ++i) v[i] = value(*a->get(i), "rectangle", Dimension::length);
      if (!(v[2] > 0.0 && v[3] > 0.0)) throw InputError(key_at(*n, "rectangle") + ": width and height must be positive");
      return {{v[0], v[1]}, {v[0] + v[2], v[1]}, {v[0] + v[2], v[1] + v[3]}, {v[0], v[1] + v[3]}};
    }
    if (const toml::node* n = t.get("polygon")) {
      const auto* a = n->as_array();
      if (!a || a->size() < 3) throw InputError(key_at(*n, "polygon") + ": expected at least 3 points [[x, y], ...]");
      Polygon p;
      for (const auto& e : *a) p.push_back(point(e, "polygon"));
      if (!is_simple(p)) throw InputError(key_at(*n, "polygon") + ": the polygon intersects itself or has zero area");
      return p;
    }
    throw InputError(here() + ": give " + what + " as rectangle = [x0, y0, width, height] or polygon = [[x, y], ...]");
  }
  std::vector<TomlTable> entries(const std::string& key) const {
    std::vector<TomlTable> out;
    const toml::node* n = t.get(key);
    if (!n) return out;
    const auto* a = n->as_array();
    if (!a) throw InputError(key_at(*n, key) + ": expected an array of tables, written [[" + path + "." + key + "]]");
    for (const auto& e : *a) {
      const auto* et = e.as_table();
      if (!et) throw InputError(key_at(e, key) + ": expected a table, written [[" + path + "." + key + "]]");
      out.push_back({*et, file, path + "." + key});
    }
    return out;
  }
  // The entry's name, unique among `seen` (the names of sets, joints, openings and regions all
  // become joint or group names).
  std::string name(std::set<std::string>& seen) const {
    const std::string n = text("name");
    if (n.empty()) throw InputError(key_at(required("name"), "name") + ": must not be empty");
    if (!seen.insert(n).second)
      throw InputError(key_at(required("name"), "name") + ": the name '" + n + "' is used twice in [rock_mass]");
    return n;
  }
};

}  // namespace rockdem
