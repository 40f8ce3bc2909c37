#pragma once
// Removing blocks from a model (excavation): their gridpoints, zones and contacts are deleted and
// the model's arrays renumbered. Block::id of the blocks that remain does not change (contact keys
// and outputs name blocks by id); their positions in Model::blocks, and every gridpoint and zone
// index, do. Whatever else stores positions (boundary conditions, histories, the engine's
// per-block arrays, the case's block names) is renumbered with the maps returned.
#include <vector>

#include "framework/model/model.hpp"

namespace rockdem {

// Old index -> new index, -1 for what was removed.
struct Renumbering {
  std::vector<int> gp, block, zone;
  // A gridpoint list renumbered, dropping removed points; false if any was removed.
  bool points(std::vector<int>& list) const;
};

// Removes the blocks at the given positions (any order, duplicates allowed) and renumbers.
// GridPoint::block becomes the block's new position.
Renumbering remove_blocks(Model& m, const std::vector<int>& blocks);

}  // namespace rockdem
