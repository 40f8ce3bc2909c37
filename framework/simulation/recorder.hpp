#pragma once
// Sampling a running case: its named histories into history.h5 and, for direct-shear cases, the
// measurement-format columns.
#include <cmath>
#include <filesystem>
#include <string>

#include "framework/io/case.hpp"
#include "framework/io/history.hpp"
#include "framework/io/measurement_csv.hpp"
#include "framework/mechanics/engine.hpp"

namespace rockdem {

// Samples the case's histories and, for direct-shear cases, the measurement-format columns.
class Recorder {
 public:
  Recorder(const Case& c, const Engine& e, const std::filesystem::path& history_file);

  void stage_started(int index, const std::string& name);
  void sample();

  void close() { h_.close(); }
  void flush() { h_.flush(); }
  MeasurementFile& lab() { return lab_; }
  History& history() { return h_; }

 private:
  double mean_y(const std::vector<int>& pts) const;
  double normal_disp() const;
  double value(const HistorySpec& s) const;

  const Case& c_;
  const Engine& e_;
  History h_;
  int stage_id_ = 0;
  int ds_[3] = {-1, -1, -1};
  int stage_ = 0;
  int test_stage_ = 0;  // 1-based test stage of the current shear stage, 0 outside them
  double loader_x0_ = 0.0, normal0_ = 0.0, t0_ = NAN;
  MeasurementFile lab_;
};

void write_lab_record(const Case& c, MeasurementFile& f, const std::filesystem::path& path, const std::string& status);

}  // namespace rockdem
