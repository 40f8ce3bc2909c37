#pragma once
// Checkpoints: the complete evolving state of a Model in one HDF5 file, bit for bit (doubles are
// stored natively, joint and rock-material state as raw bytes). Used for the last good state of a
// run that goes unstable and for restarts.
//
// A checkpoint is restored into a Model built from the same case: the blocks, gridpoints and zones
// must match in number and identity (block ids and names, gridpoint (block, local) ids, zone
// connectivity, joint-model names). Anything else is an InputError naming the file and what
// differs, and leaves the Model untouched. Contacts come back with their joint-law state as they
// were (ContactStore::restore), not re-initialised.
//
// Layout (h5py-readable): attributes format, version, time, step, thickness, gravity on /;
// groups /gridpoints, /zones, /blocks, /contacts with one dataset per field (vectors as n x 2,
// stresses n x 3, state blocks n x bytes of uint8); /extra holds caller scalars as attributes.
// The per-item datasets and the root scalars are the fields listed in
// framework/model/state_fields.hpp: a field added there is written and read back.
#include <map>
#include <string>
#include <vector>

namespace rockdem {

struct Model;

// Engine state that lives outside the Model (stage index, time step, loading-block travel, ...).
using CheckpointScalars = std::map<std::string, double>;

// State that lives outside the Model as named arrays (boundary conditions' own state, e.g. the
// forces a quiet boundary holds and a free-field column's motion), in the group /arrays.
using CheckpointArrays = std::map<std::string, std::vector<double>>;

// Text that lives outside the Model (the case as it was run, which a restart compares with its
// own), in the group /texts as byte datasets (no attribute size limit; h5py: bytes(...).decode()).
using CheckpointTexts = std::map<std::string, std::string>;

// Writes to `path` + ".tmp" and renames, so an existing checkpoint survives a crash mid-write.
void write_checkpoint(const Model& m, const std::string& path, const CheckpointScalars& extra = {},
                      const CheckpointArrays& arrays = {}, const CheckpointTexts& texts = {});

// The arrays of a checkpoint (none for checkpoints without the group).
CheckpointArrays read_checkpoint_arrays(const std::string& path);
// The caller scalars of a checkpoint (/extra), without reading the model.
CheckpointScalars read_checkpoint_scalars(const std::string& path);
// The step of the state a checkpoint holds, without reading the model.
long read_checkpoint_step(const std::string& path);
// The texts of a checkpoint (none for checkpoints without the group).
CheckpointTexts read_checkpoint_texts(const std::string& path);

// Restores the state written by write_checkpoint into `m` and returns the extra scalars.
CheckpointScalars read_checkpoint(Model& m, const std::string& path);

}  // namespace rockdem
