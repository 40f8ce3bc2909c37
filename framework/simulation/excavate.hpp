#pragma once
// Excavation at the start of a stage (StageSpec::excavate): removes the blocks from the model and
// renumbers everything that refers to model positions: the engine's boundary conditions, the
// case's histories, block names and direct-shear blocks. With relax_steps > 0 the forces the
// removed blocks exerted on the others (their contacts' last forces) are applied to the
// gridpoints that felt them and reduced linearly to zero over that many steps of the stage.
#include "framework/io/case_data.hpp"
#include "framework/mechanics/engine.hpp"

namespace rockdem {

// Removes the stage's blocks; returns the number removed.
std::size_t excavate(Case& c, Engine& e, const StageSpec& stage);

}  // namespace rockdem
