#pragma once
// A DEM case: the TOML case file turned into a Model, an Engine's settings and boundary
// conditions, stages, histories and outputs. Every input problem is an InputError that names the
// file, the line or key, what is wrong and what is valid, raised before any computation.
// The case-file keys are documented in docs/case-files.md. The file is read table by table into
// plain specs (case_reader.hpp, case_spec.hpp), which case_builder.hpp turns into the Case
// (case_data.hpp).
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <toml++/toml.h>

#include "framework/io/case_data.hpp"

namespace rockdem {

// What `rockdem run` changes in a case file from its command line. Each is recorded in the
// case's source text (Case::source_toml), so a restart must give the same.
struct CaseOverrides {
  // --joint NAME=FILE: the [[joints]] entry NAME takes its law, parameters and effects from FILE
  // (CaseReader::joint); a NAME that no entry has is an InputError.
  std::map<std::string, std::string> joint_files;
  // --seed N: [rock_mass] seed, another realisation of the same joint sets (a case without a
  // [rock_mass] table is an InputError).
  std::optional<std::int64_t> rock_mass_seed;
  // --excavate STAGE=NAME,...: what the [[stages]] entry STAGE excavates instead of its own
  // `excavate` (blocks or groups; empty: nothing), e.g. a drift's overbreak chosen for another
  // realisation. A STAGE the case does not have is an InputError listing its stages.
  std::map<std::string, std::vector<std::string>> excavate;
  // --motion [STAGE=]NAME[,NAME] and --pgv [STAGE=]VALUE: the earthquake a stage plays and its
  // peak ground velocity, e.g. an event sequence at other levels or with other records. The key
  // "" stands for every stage that plays a motion; a named stage wins over it. Only stages that
  // already play a motion can be given one (a static stage lacks a dynamic stage's keys); a
  // name the case's [[motions]] lacks is refused with its motions listed. --pgv replaces the
  // stage's motion_scale, pga or pgv. The value is checked as a velocity ("1 m/s").
  std::map<std::string, std::vector<std::string>> motion;
  std::map<std::string, std::string> pgv;
};

// Read a case file. `name` is used in messages; `text` (optional) is parsed instead of the file
// (the built-in default case).
Case load_case(const std::string& path, const CaseOverrides& overrides = {});
Case load_case_text(const std::string& text, const std::string& name, const std::string& base_dir);
// A case already parsed (or built in code, e.g. the direct-shear specimen of a laboratory test).
Case load_case_table(const toml::table& root, const std::string& name, const std::string& base_dir);

}  // namespace rockdem
