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
// completed stages); `restart` names one to continue from: the model state is read back and the
// run goes on with the next stage, repeating exactly what the uninterrupted run would do.
// `comm`: the processes of a domain-decomposed run (framework/parallel/); every process calls
// run_case with the same case, process 0 writes the outputs.
RunResult run_case(Case& c, const std::filesystem::path& out, bool quiet, const std::string& restart = "",
                   Communication& comm = serial_communication());

}  // namespace rockdem
