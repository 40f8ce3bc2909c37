#pragma once
// What a restart may change in its case. A run restarted from a checkpoint written after
// `completed` stages must be the run the checkpoint's case would have gone on with, so the case
// may change or add only what the completed stages never used: the stages still to run, boundary
// conditions active only in them (appended after the others: conditions keep their state by
// position), ground motions no completed stage played, and the direct-shear test stages still to
// run. Everything else that differs (a stiffness, a history, the output settings) is named.
#include <cstddef>
#include <string>
#include <vector>

namespace rockdem {

// One line per difference, "key: <value> in the checkpoint's case, <value> in this one" (or
// absent from one of them), in the order of the files; empty when the restart may go on.
// `before` and `now` are Case::source_toml of the two cases.
std::vector<std::string> restart_differences(const std::string& before, const std::string& now, std::size_t completed);

}  // namespace rockdem
