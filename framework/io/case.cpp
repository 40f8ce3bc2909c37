#include "framework/io/case.hpp"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "framework/core/did_you_mean.hpp"
#include "framework/core/error.hpp"
#include "framework/core/names.hpp"
#include "framework/io/case_builder.hpp"
#include "framework/io/case_reader.hpp"
#include "framework/io/rock_mass_reader.hpp"

namespace rockdem {
namespace {

namespace fs = std::filesystem;

// The case as read, for a restart to compare with (case_comparison.hpp): the parsed file, plus
// a table `--joint` with the text of each --joint file by joint name.
std::string source_text(const toml::table& root, const std::map<std::string, std::string>& joint_files) {
  toml::table t = root;
  if (!joint_files.empty()) {
    toml::table j;
    for (const auto& [name, f] : joint_files) {
      std::ifstream is(f);
      std::ostringstream text;
      text << is.rdbuf();
      j.insert(name, text.str());
    }
    t.insert("--joint", std::move(j));
  }
  std::ostringstream os;
  os << t;
  return os.str();
}

Case build(const toml::table& root, const CaseReader& r, const std::map<std::string, std::string>& joint_files = {}) {
  CaseBuilder b(r.file(), r.top_level(root));
  const auto* model = root["model"].as_table();
  b.model_settings(model ? r.model_settings(*model) : ModelSettingsSpec{});
  if (const auto* t = root["time"].as_table()) b.time(r.time(*t));
  for (const auto* t : r.tables(root, "materials")) b.add_material(r.material(*t));
  std::vector<std::string> joint_names;
  for (const auto* t : r.tables(root, "joints")) {
    const auto* n = t->get("name");
    const std::string name = n && n->is_string() ? n->as_string()->get() : std::string();
    const auto it = joint_files.find(name);
    b.add_joint(r.joint(*t, it == joint_files.end() ? std::string() : it->second));
    joint_names.push_back(name);
  }
  for (const auto& [name, f] : joint_files)
    if (std::find(joint_names.begin(), joint_names.end(), name) == joint_names.end())
      throw InputError("--joint " + name + "=" + f + ": " + r.file() + " has no [[joints]] entry '" + name + "'" +
                       did_you_mean(name, joint_names) + "; its joints: " + join_names(joint_names));
  for (const auto* t : r.tables(root, "blocks")) b.add_block(r.block(*t));
  if (const auto* t = root["rock_mass"].as_table())
    for (const auto& s : rock_mass_blocks(read_rock_mass(*t, r.file()))) b.add_block(s);
  b.finish_blocks();
  if (const auto* t = root["in_situ"].as_table()) b.in_situ(r.in_situ(*t));
  for (const auto* t : r.tables(root, "motions")) b.add_motion(r.motion(*t));
  for (const auto* t : r.tables(root, "boundary")) b.add_boundary(r.boundary(*t));
  for (const auto* t : r.tables(root, "stages")) b.add_stage(r.stage(*t));
  b.finish_stages();
  for (const auto* t : r.tables(root, "histories")) b.add_history(r.history(*t));
  if (const auto* t = root["direct_shear"].as_table()) b.direct_shear(r.direct_shear(*t));
  if (const auto* t = root["drift"].as_table()) b.drift(r.drift(*t));
  if (const auto* t = root["output"].as_table()) b.output(r.output(*t));
  Case c = b.finish();
  c.source_toml = source_text(root, joint_files);
  return c;
}

Case parse(const std::string& text, const std::string& name, const std::string& base_dir, bool from_file,
           const std::map<std::string, std::string>& joint_files = {}) {
  toml::table root;
  try {
    root = from_file ? toml::parse_file(name) : toml::parse(text, name);
  } catch (const toml::parse_error& e) {
    throw InputError(name + ":" + std::to_string(e.source().begin.line) + ":" + std::to_string(e.source().begin.column) +
                     ": TOML syntax error: " + std::string(e.description()));
  }
  return build(root, CaseReader(name, base_dir), joint_files);
}

}  // namespace

int Case::block_index(const std::string& name, const std::string& where) const {
  for (std::size_t i = 0; i < block_names.size(); ++i)
    if (block_names[i] == name) return static_cast<int>(i);
  throw InputError(where + ": unknown block '" + name + "'; blocks: " + join_names(block_names));
}

Case load_case(const std::string& path, const std::map<std::string, std::string>& joint_files) {
  if (!fs::exists(path)) throw InputError(path + ": case file does not exist");
  return parse("", path, fs::path(path).parent_path().string(), true, joint_files);
}

Case load_case_text(const std::string& text, const std::string& name, const std::string& base_dir) {
  return parse(text, name, base_dir, false);
}

Case load_case_table(const toml::table& root, const std::string& name, const std::string& base_dir) {
  return build(root, CaseReader(name, base_dir));
}

}  // namespace rockdem
