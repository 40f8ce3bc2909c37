#include "framework/io/case.hpp"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <set>
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

// A rock-mass block named <prefix>.<k>: which block that is follows the realisation of the
// joint sets (rock_mass_spec.hpp), unlike an opening's blocks, named after the opening.
bool numbered_rock_block(const std::string& name, const std::string& prefix) {
  if (name.size() <= prefix.size() + 1 || name.compare(0, prefix.size(), prefix) != 0 || name[prefix.size()] != '.') return false;
  return std::all_of(name.begin() + static_cast<std::ptrdiff_t>(prefix.size()) + 1, name.end(),
                     [](char ch) { return ch >= '0' && ch <= '9'; });
}

// With --seed, a case that names numbered rock-mass blocks (to excavate them, or in a boundary or
// a history) names other blocks than its author saw: the drift study's overbreak, three shoulder
// blocks of seed 2026, took away the far field's right half with seed 2. Refused, naming the key
// and what the block is in the new realisation.
void check_seeded_names(const toml::table& root, const CaseReader& r, const std::vector<BlockSpec>& blocks,
                        const std::string& prefix, std::int64_t seed) {
  // Hand-written [[blocks]] keep their names whatever the seed, and names the command line gave
  // (--excavate, a line-less node) were chosen for this realisation.
  std::set<std::string> written;
  for (const auto* t : r.tables(root, "blocks"))
    if (const auto* n = t->get_as<std::string>("name")) written.insert(n->get());
  auto check = [&](const toml::node& e, const std::string& key) {
    const auto* name = e.as_string();
    if (!name || e.source().begin.line == 0 || written.count(name->get()) || !numbered_rock_block(name->get(), prefix)) return;
    std::string now = "no block of this realisation";
    for (const BlockSpec& b : blocks)
      if (b.name == name->get()) now = "a block of group '" + b.group + "' in this realisation";
    throw InputError(r.file() + ":" + std::to_string(e.source().begin.line) + " key '" + key + "': names block '" + name->get() +
                     "' by its number, and --seed " + std::to_string(seed) +
                     " draws another realisation of the joint sets, in which the blocks are numbered afresh ('" + name->get() +
                     "' is " + now + "); name the rock mass's openings or block groups, or select by location (line or box), "
                     "which do not change with the seed (a stage's list for this realisation: --excavate STAGE=NAME,...; loose blocks: "
                     "the stage's scale_off), or run the case with its own seed");
  };
  for (const auto* t : r.tables(root, "stages"))
    if (const auto* ex = (*t)["excavate"].as_array()) {
      const auto* nm = (*t)["name"].as_string();
      for (const toml::node& e : *ex) check(e, "stages." + (nm ? nm->get() : std::string("?")) + ".excavate");
    }
  for (const char* table : {"boundary", "histories"})
    for (const auto* t : r.tables(root, table))
      if (const toml::node* b = t->get("block")) check(*b, std::string(table) + ".block");
}

Case build(const toml::table& root, const CaseReader& r, const std::map<std::string, std::string>& joint_files = {},
           std::optional<std::int64_t> seed = {}) {
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
  if (const auto* t = root["rock_mass"].as_table()) {
    const RockMassSpec spec = read_rock_mass(*t, r.file());
    const std::vector<BlockSpec> generated = rock_mass_blocks(spec);
    if (seed) check_seeded_names(root, r, generated, spec.prefix, *seed);
    for (const auto& s : generated) b.add_block(s);
  }
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

// The [[stages]] entry called `stage`, or an InputError for `option` (the command line's words)
// that lists the stages of the case file `file`.
toml::table* named_stage(toml::table& root, const std::string& stage, const std::string& option, const std::string& file) {
  std::vector<std::string> stages;
  toml::table* found = nullptr;
  if (toml::array* list = root["stages"].as_array())
    for (toml::node& n : *list)
      if (toml::table* t = n.as_table()) {
        const auto* nm = t->get_as<std::string>("name");
        if (!nm) continue;
        stages.push_back(nm->get());
        if (nm->get() != stage) continue;
        if (found)
          throw InputError(option + ": " + file + " has two stages named '" + stage + "'; the option cannot tell which " +
                           "(name each stage once)");
        found = t;
      }
  if (!found)
    throw InputError(option + ": " + file + " has no stage '" + stage + "'" + did_you_mean(stage, stages) + "; its stages: " +
                     join_names(stages));
  return found;
}

// --motion and --pgv (CaseOverrides): set in the stage tables, so that the case's source text
// (and a restart's comparison) has them. The motion names themselves are checked where the stage
// is read, against the case's [[motions]].
void set_events(toml::table& root, const CaseOverrides& overrides, const std::string& file) {
  if (overrides.motion.empty() && overrides.pgv.empty()) return;
  std::vector<std::pair<std::string, toml::table*>> playing;  // stages that play a motion, in order
  if (toml::array* list = root["stages"].as_array())
    for (toml::node& n : *list)
      if (toml::table* t = n.as_table(); t && t->contains("motion")) {
        const auto* nm = t->get_as<std::string>("name");
        playing.emplace_back(nm ? nm->get() : std::string("(unnamed)"), t);
      }
  std::vector<std::string> playing_names;
  for (const auto& p : playing) playing_names.push_back(p.first);
  // The stages an option names: one, or (key "") every stage that plays a motion.
  auto targets = [&](const std::string& stage, const std::string& option) {
    std::vector<toml::table*> out;
    if (stage.empty()) {
      if (playing.empty())
        throw InputError(option + ": " + file + " has no stage that plays an earthquake (a [[stages]] entry with motion = " +
                         "\"...\"); the option changes those stages");
      for (const auto& p : playing) out.push_back(p.second);
      return out;
    }
    toml::table* t = named_stage(root, stage, option, file);
    if (!t->contains("motion"))
      throw InputError(option + ": stage '" + stage + "' of " + file + " plays no motion, so it has nothing to change; " +
                       (playing.empty() ? std::string("the case has no stage that does")
                                        : "stages that play one: " + join_names(playing_names)));
    out.push_back(t);
    return out;
  };
  // std::map puts the key "" first: the every-stage value is set before the named stages' over it.
  for (const auto& [stage, names] : overrides.motion) {
    std::string list;
    for (const auto& m : names) list += (list.empty() ? "" : ",") + m;
    const std::string option = "--motion " + (stage.empty() ? "" : stage + "=") + list;
    for (toml::table* t : targets(stage, option)) {
      // A stage that plays a horizontal and a vertical record keeps both: one name for it
      // would drop the vertical without a word.
      const toml::array* had = t->get_as<toml::array>("motion");
      const std::size_t n_had = had ? had->size() : 1;
      if (n_had != names.size()) {
        const auto* nm = t->get_as<std::string>("name");
        throw InputError(option + ": stage '" + (nm ? nm->get() : std::string("?")) + "' of " + file + " plays " +
                         std::to_string(n_had) + (n_had == 1 ? " motion" : " motions") + ", the option names " +
                         std::to_string(names.size()) + "; give as many, e.g. --motion STAGE=H,V for two (each " +
                         "name a [[motions]] entry, whose direction is its own)");
      }
      if (names.size() == 1) {
        t->insert_or_assign("motion", names.front());
      } else {
        toml::array a;
        for (const auto& m : names) a.push_back(m);
        t->insert_or_assign("motion", std::move(a));
      }
    }
  }
  for (const auto& [stage, value] : overrides.pgv) {
    for (toml::table* t : targets(stage, "--pgv " + (stage.empty() ? "" : stage + "=") + value)) {
      t->erase("motion_scale");
      t->erase("pga");
      t->insert_or_assign("pgv", value);
    }
  }
}

Case parse(const std::string& text, const std::string& name, const std::string& base_dir, bool from_file,
           const CaseOverrides& overrides = {}) {
  toml::table root;
  try {
    root = from_file ? toml::parse_file(name) : toml::parse(text, name);
  } catch (const toml::parse_error& e) {
    throw InputError(name + ":" + std::to_string(e.source().begin.line) + ":" + std::to_string(e.source().begin.column) +
                     ": TOML syntax error: " + std::string(e.description()));
  }
  for (const auto& [stage, names] : overrides.excavate) {
    toml::table* found = named_stage(root, stage, "--excavate " + stage + "=...", name);
    toml::array list;
    for (const auto& n : names) list.push_back(n);
    // Set in the table, so that the case's source text (and a restart's comparison) has it.
    if (list.empty()) found->erase("excavate");
    else found->insert_or_assign("excavate", std::move(list));
  }
  set_events(root, overrides, name);
  if (overrides.rock_mass_seed) {
    // Set in the table itself, so that the case's source text (and a restart's comparison)
    // carries the seed the model was drawn with.
    toml::table* rm = root["rock_mass"].as_table();
    if (!rm)
      throw InputError("--seed " + std::to_string(*overrides.rock_mass_seed) + ": " + name +
                       " has no [rock_mass] table; the seed draws a rock mass's joint sets (docs/case-files.md, [rock_mass])");
    // The case's own seed (the generator's default, 1, when it gives none) draws the blocks its
    // author named: only another seed renumbers them.
    const auto* own = rm->get("seed");
    const std::int64_t case_seed = own && own->as_integer() ? own->as_integer()->get() : static_cast<std::int64_t>(RockMassInput{}.seed);
    // (Left as it is then, so that a restart without --seed compares equal.)
    if (*overrides.rock_mass_seed == case_seed) return build(root, CaseReader(name, base_dir), overrides.joint_files);
    rm->insert_or_assign("seed", *overrides.rock_mass_seed);
  }
  return build(root, CaseReader(name, base_dir), overrides.joint_files, overrides.rock_mass_seed);
}

}  // namespace

int Case::block_index(const std::string& name, const std::string& where) const {
  for (std::size_t i = 0; i < block_names.size(); ++i)
    if (block_names[i] == name) return static_cast<int>(i);
  throw InputError(where + ": unknown block '" + name + "'; blocks: " + join_names(block_names));
}

Case load_case(const std::string& path, const CaseOverrides& overrides) {
  if (!fs::exists(path)) throw InputError(path + ": case file does not exist");
  return parse("", path, fs::path(path).parent_path().string(), true, overrides);
}

Case load_case_text(const std::string& text, const std::string& name, const std::string& base_dir) {
  return parse(text, name, base_dir, false);
}

Case load_case_table(const toml::table& root, const std::string& name, const std::string& base_dir) {
  return build(root, CaseReader(name, base_dir));
}

}  // namespace rockdem
