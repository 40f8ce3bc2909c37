#pragma once
// Reading [rock_mass] of a case file (keys in docs/case-files.md) into a RockMassSpec. What is
// about how the table is written (unknown keys, units, types, required keys, values out of range)
// is checked here with the file and line; the geometry (openings inside the domain, sets that cut
// nothing, ...) is checked by the generator with the places this reader puts into the spec.
#include <string>

#include <toml++/toml.h>

#include "framework/io/rock_mass_spec.hpp"

namespace rockdem {

RockMassSpec read_rock_mass(const toml::table& t, const std::string& file);

}  // namespace rockdem
