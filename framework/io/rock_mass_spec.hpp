#pragma once
// [rock_mass] as plain data: the generator's input (framework/geometry/rock_mass.hpp) and what
// the blocks are made of, how they are named and grouped. The reader
// (framework/io/rock_mass_reader.cpp) fills it from a case file; rock_mass_blocks() turns it into
// BlockSpecs with edge labels that the case builder adds like hand-written [[blocks]].
// The rules and keys are in docs/rock-mass-generator.md and docs/case-files.md.
#include <string>
#include <vector>

#include "framework/geometry/rock_mass.hpp"
#include "framework/io/case_spec.hpp"

namespace rockdem {

struct RockMassSpec {
  RockMassInput geometry;
  bool rigid = true;
  double density = 0.0;        // rigid blocks [kg/m3]
  std::string material;        // deformable blocks: a [[materials]] name
  double zone_size = 0.0;      // deformable blocks [m]; a region's zone_size overrides it
  std::string group = "rock";  // group of the blocks in no region
  std::string prefix = "rm";   // block names: <prefix>.<k>
  std::string where, material_where;
};

// The generated blocks as BlockSpecs, in the generator's order: rock blocks named <prefix>.<k>
// (k counting rock blocks only) with group = their region's name (or `group`), opening blocks named
// after the opening (<opening>.<k> if a region outline cuts it into several) with group = the
// opening's name. Edge labels name the joint set or named joint and the bridge flag; glued cuts
// are bridges of joint "" and the domain outline has none. `out` receives the cut rock mass.
std::vector<BlockSpec> rock_mass_blocks(const RockMassSpec& spec, RockMass* out = nullptr);

}  // namespace rockdem
