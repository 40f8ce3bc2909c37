#pragma once
// Excavation at the start of a stage (StageSpec::excavate): removes the blocks from the model and
// renumbers everything that refers to model positions: the engine's boundary conditions, the
// case's histories, block names and direct-shear blocks. With relax_steps > 0 the forces the
// removed blocks exerted on the others (their contacts' last forces) are applied to the
// gridpoints that felt them and reduced linearly to zero over that many steps of the stage.
#include "framework/io/case_data.hpp"
#include "framework/mechanics/engine.hpp"

namespace rockdem {

// Removes the stage's blocks and renumbers `conditions` (the engine's, or the case's before an
// engine exists); returns the number removed. With `relax` given and relax_steps > 0, sets it to
// the condition that releases the removed blocks' forces (for the engine to add).
std::size_t excavate(Case& c, const std::vector<std::unique_ptr<BoundaryCondition>>& conditions, const StageSpec& stage,
                     std::unique_ptr<BoundaryCondition>* relax = nullptr);

// Takes the blocks with these ids out of the model with the same renumbering as an excavation,
// releasing no forces (a stage's scale_off: loose blocks that fell away); returns the renumbering
// (empty maps when no block had one of the ids).
Renumbering take_out_blocks(Case& c, const std::vector<std::unique_ptr<BoundaryCondition>>& conditions,
                            const std::vector<BlockId>& ids);

}  // namespace rockdem
