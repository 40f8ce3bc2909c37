#pragma once
// The measurement of a direct-shear test on a DEM specimen, in the measurement format
// (docs/measurement-format.md; the quantities are those of DirectShearSpec): three columns of
// the run's history, sampled with it, and the rows of the joint test record, written at the end.
#include <cmath>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "framework/io/case.hpp"
#include "framework/io/history.hpp"
#include "framework/io/measurement_csv.hpp"
#include "framework/mechanics/engine.hpp"

namespace rockdem {

class DirectShearRecorder {
 public:
  // For a case with [direct_shear]; defines its three columns in `h` (before h's first sample).
  DirectShearRecorder(const Case& c, const Engine& e, History& h);

  // A case stage begins; one of the shear stages starts its test stage (numbered in test order),
  // whose displacements are measured from here.
  void stage_started(const std::string& name);
  // Sets the joint columns of the row `h` is recording and, in a test stage, adds a record row.
  // Throws InstabilityError once the joint has dilated beyond the contact detection distance.
  void sample(History& h);

  MeasurementFile& record() { return record_; }
  // The record so far and the origin of its time, for a stage checkpoint; a restarted run puts
  // them back and writes the whole record, as the uninterrupted run does. (Displacements are
  // measured from each test stage's start, which checkpoints at stage ends never fall inside.)
  std::map<std::string, std::vector<double>> saved_state() const;
  void restore_state(const std::map<std::string, std::vector<double>>& a, const std::string& file);
  // Write the record with its metadata to <dir>/<specimen>.csv, or, for a run that stopped, to
  // <dir>/<specimen>.incomplete.csv marked as such; they return the path, or an empty path (and
  // write nothing) when no test stage was sampled.
  std::filesystem::path write(const std::filesystem::path& dir);
  std::filesystem::path write_incomplete(const std::filesystem::path& dir);

 private:
  double mean_y(const std::vector<int>& pts) const;
  double normal_disp() const;
  std::filesystem::path write_record(const std::filesystem::path& path, const std::string& status);

  const Case& c_;
  const Engine& e_;
  int ds_[3] = {-1, -1, -1};
  int test_stage_ = 0;  // 1-based test stage of the current shear stage, 0 outside them
  double loader_x0_ = 0.0, normal0_ = 0.0, t0_ = NAN;
  MeasurementFile record_;
};

}  // namespace rockdem
