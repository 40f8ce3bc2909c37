#pragma once
// `rockdem run CASE --write-blocks DIR`: the blocks of a built case written for inspection
// before anything runs: DIR/blocks.vtu (one polygon a block: block_id, group, rigid, region,
// opening), DIR/traces.vtu (the rock mass's joint traces, bridges and glued cuts as lines) and
// DIR/blocks.csv (one row a block). Region and opening come from the case's [rock_mass], which is
// cut again (the same seed gives the same blocks).
#include <filesystem>
#include <string>

#include "framework/io/case_data.hpp"

namespace rockdem {

// `case_file` empty: the case has no file (the built-in default), so no [rock_mass].
// Returns a one-line summary.
std::string write_blocks_for_inspection(const Case& c, const std::string& case_file, const std::filesystem::path& dir);

}  // namespace rockdem
