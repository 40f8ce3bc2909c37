#pragma once
// Sampling a running case: its named histories (and, for direct-shear cases, the joint
// measurement's columns) into history.h5, written as the run goes.
#include <filesystem>
#include <map>
#include <vector>
#include <optional>
#include <string>

#include "framework/io/case.hpp"
#include "framework/io/history.hpp"
#include "framework/lab/direct_shear_recorder.hpp"
#include "framework/mechanics/engine.hpp"

namespace rockdem {

class Recorder {
 public:
  Recorder(Case& c, const Engine& e, const std::filesystem::path& history_file);

  void stage_started(int index, const std::string& name);
  // A stage resumed from a checkpoint written within it: what it measures from came back with
  // restore_state.
  void stage_resumed(int index) { stage_ = index; }
  void sample();

  // The samples so far (and the joint test record), for a stage checkpoint; a run restarted from
  // it begins its history with them, so that it holds the whole run as the uninterrupted one does.
  std::map<std::string, std::vector<double>> saved_state() const;
  // InputError naming `file` when the checkpoint's series are not this case's.
  void restore_state(const std::map<std::string, std::vector<double>>& a, const std::string& file);

  void close() { h_.close(); }
  void flush() { h_.flush(); }
  History& history() { return h_; }
  // The direct-shear measurement of a case with [direct_shear], null otherwise.
  DirectShearRecorder* direct_shear() { return direct_shear_ ? &*direct_shear_ : nullptr; }

 private:
  double value(const HistorySpec& s) const;

  Case& c_;
  const Engine& e_;
  History h_;
  int stage_id_ = 0;
  int stage_ = 0;
  bool needs_state_ = false;  // some quantity is read from the model's state (Reduction::state)
  unsigned state_parts_ = 0;  // what of the state they read besides motion and gridpoints
  std::optional<DirectShearRecorder> direct_shear_;
};

}  // namespace rockdem
