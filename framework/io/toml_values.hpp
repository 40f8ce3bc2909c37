#pragma once
// TOML (toml++) to RawValues: the bridge between case files and typed parameters. Every value
// remembers where it was written ("file:line key table.key") so that the parameter checks in
// framework/core/params.hpp can name the place of a mistake.
#include <initializer_list>
#include <string>
#include <string_view>

#include <toml++/toml.h>

#include "framework/core/params.hpp"

namespace rockdem {

// Parses a TOML file; a missing file or a syntax error is an InputError naming the file, line and
// column. `what` names the kind of file in the not-found message (e.g. "case file").
toml::table parse_toml_file(const std::string& path, const std::string& what);

// "file:line" of a node (line 0 when toml++ has no source position, e.g. a built table).
std::string toml_where(const toml::node& node, const std::string& file);

// One scalar value: string, integer, float or boolean. Arrays, tables and dates are an
// InputError naming the place and what is accepted. `key_path` is e.g. "joint.params.kn".
RawValue raw_value(const toml::node& node, const std::string& file, const std::string& key_path);

// Every key of `table` as a RawValue with where = "file:line key table_path.key". Nested tables
// and arrays are InputErrors: name such keys in `skip`. Prefer `skip` to erasing keys from a
// copy of the table: toml++ copies do not keep source positions (the lines would read 0).
RawValues raw_values(const toml::table& table, const std::string& file, const std::string& table_path,
                     std::initializer_list<std::string_view> skip = {});

}  // namespace rockdem
