#pragma once
// Reading a case file: each table of the parsed TOML into its plain spec (case_spec.hpp), one
// function per table. Everything that is about how the file is written is checked here (unknown
// keys, types, units, required keys, names of choices), with messages naming the file and line;
// what depends on the rest of the model (block names, materials, stages) is the builder's
// (case_builder.hpp), with the places the reader puts into the specs.
// The keys are documented in docs/case-files.md.
#include <string>
#include <vector>

#include <toml++/toml.h>

#include "framework/io/case_spec.hpp"

namespace rockdem {

class CaseReader {
 public:
  // `file` names the case in messages; relative data-file paths start from `base_dir`.
  CaseReader(std::string file, std::string base_dir) : file_(std::move(file)), base_dir_(std::move(base_dir)) {}
  const std::string& file() const { return file_; }

  // The top level: its keys, the tables written [name], and the title.
  std::string top_level(const toml::table& root) const;
  // The entries of an array of tables [[key]] (none if the key is absent).
  std::vector<const toml::table*> tables(const toml::table& root, const std::string& key) const;

  ModelSettingsSpec model_settings(const toml::table& t) const;  // [model]
  TimeSpec time(const toml::table& t) const;                     // [time]
  MaterialSpec material(const toml::table& t) const;             // [[materials]]
  // [[joints]]; `replacement` (rockdem run --joint NAME=FILE): the law, parameters and effects
  // come from FILE (a TOML table of those keys, or a calibrate/diagnose JSON) instead of `t`.
  JointSpec joint(const toml::table& t, const std::string& replacement = "") const;
  BlockSpec block(const toml::table& t) const;                   // [[blocks]]
  InSituSpec in_situ(const toml::table& t) const;                // [in_situ]
  MotionSpec motion(const toml::table& t) const;                 // [[motions]] (motion_reader.cpp)
  BoundarySpec boundary(const toml::table& t) const;             // [[boundary]]
  StageInput stage(const toml::table& t) const;                  // [[stages]]
  HistoryInput history(const toml::table& t) const;              // [[histories]]
  DirectShearInput direct_shear(const toml::table& t) const;     // [direct_shear]
  DriftInput drift(const toml::table& t) const;                  // [drift]
  OutputSpec output(const toml::table& t) const;                 // [output]

 private:
  std::string file_, base_dir_;
};

// A checkpoint interval, "N steps" (of the run) or a wall-clock time ("30 min"), into `o`
// (replacing both of its intervals); InputError naming `where` otherwise.
void read_checkpoint_interval(const std::string& text, const std::string& where, OutputSpec& o);

}  // namespace rockdem
