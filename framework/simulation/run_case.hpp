#pragma once
#include <filesystem>

#include "framework/io/case.hpp"
#include "framework/io/history.hpp"
#include "framework/io/measurement_csv.hpp"
#include "framework/model/communication.hpp"

namespace rockdem {

struct RunResult {
  History history;           // every sampled series (also in <out>/history.h5)
  MeasurementFile lab;       // direct-shear cases: the joint test record
  std::filesystem::path lab_csv;
};

// Run all stages of `c`, writing outputs into `out`. Throws InputError for problems found while
// running (e.g. no joint model for two blocks that touch) and InstabilityError after writing the
// last good state.
// A checkpoint is written at the end of every stage (<out>/stage_<n>_<name>.h5, with the number of
// completed stages) and at the end (final_state.h5); `restart` names one to continue from: the
// model state, the histories and joint record so far and what the engine and the boundaries carry
// are read back and the run goes on with the next stage, repeating exactly what the uninterrupted
// run would do (its history.h5 and record hold the whole run). The case may differ from the one
// that wrote the checkpoint only in the stages still to run (check_restart).
// `comm`: the processes of a domain-decomposed run (framework/parallel/); every process calls
// run_case with the same case, process 0 writes the outputs.
// The index of the stage a restart from `restart` begins with; InputError when the checkpoint is
// not one this case can go on from (an interrupted state, more stages than the case has, none left
// to run) or when the case differs from the checkpoint's in anything but the stages still to run
// (every differing key named). Reads no model; `root` prints the warning about old checkpoints.
std::size_t check_restart(const Case& c, const std::string& restart, bool root);

RunResult run_case(Case& c, const std::filesystem::path& out, bool quiet, const std::string& restart = "",
                   Communication& comm = serial_communication());

}  // namespace rockdem
