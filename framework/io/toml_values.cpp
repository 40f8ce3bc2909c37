#include "framework/io/toml_values.hpp"

#include "framework/core/error.hpp"

#include <filesystem>

namespace rockdem {

toml::table parse_toml_file(const std::string& path, const std::string& what) {
  if (!std::filesystem::exists(path)) throw InputError(path + ": " + what + " not found");
  try {
    return toml::parse_file(path);
  } catch (const toml::parse_error& e) {
    throw InputError(path + ":" + std::to_string(e.source().begin.line) + ":" + std::to_string(e.source().begin.column) +
                     ": TOML syntax error: " + std::string(e.description()));
  }
}

std::string toml_where(const toml::node& node, const std::string& file) {
  return file + ":" + std::to_string(node.source().begin.line);
}

RawValue raw_value(const toml::node& node, const std::string& file, const std::string& key_path) {
  RawValue v;
  v.where = toml_where(node, file) + " key " + key_path;
  if (const auto* s = node.as_string()) {
    v.value = s->get();
  } else if (const auto* i = node.as_integer()) {
    v.value = static_cast<std::int64_t>(i->get());
  } else if (const auto* d = node.as_floating_point()) {
    v.value = d->get();
  } else if (const auto* b = node.as_boolean()) {
    v.value = b->get();
  } else {
    const char* kind = node.is_table() ? "a table" : node.is_array() ? "an array" : "a date/time";
    throw InputError(v.where + ": " + kind + " is not a valid parameter value; write a number, a quantity "
                     "with its unit as a string (e.g. \"3 MPa\"), a name in quotes, or true/false");
  }
  return v;
}

RawValues raw_values(const toml::table& table, const std::string& file, const std::string& table_path,
                     std::initializer_list<std::string_view> skip) {
  RawValues out;
  for (const auto& [key, node] : table) {
    bool skipped = false;
    for (auto k : skip) skipped = skipped || key.str() == k;
    if (skipped) continue;
    const std::string name(key.str());
    const std::string path = table_path.empty() ? name : table_path + "." + name;
    out.emplace(name, raw_value(node, file, path));
  }
  return out;
}

}  // namespace rockdem
