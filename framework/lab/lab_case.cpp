// Reader of laboratory-test case files (see lab_case.hpp) and the element run of one.
#include "framework/lab/lab_case.hpp"

#include <chrono>
#include <filesystem>
#include <fstream>

#include "framework/core/did_you_mean.hpp"
#include "framework/core/error.hpp"
#include "framework/core/names.hpp"
#include "framework/core/units.hpp"
#include "framework/io/toml_values.hpp"
#include "rockdem_version.hpp"

namespace rockdem {
namespace {

namespace fs = std::filesystem;

struct SpecimenSettings {
  double joint_length, density, bulk, shear;
  static std::vector<Param<SpecimenSettings>> spec() {
    using P = SpecimenSettings;
    return {
        real("joint_length", &P::joint_length, Dimension::length,
             "joint length of the specimen (element: the contact length; DEM: the top block's length)")
            .positive()
            .def(1.0),
        real("density", &P::density, Dimension::density, "rock density (Table 4-1), for the DEM specimen").non_negative().def(0.0),
        real("bulk", &P::bulk, Dimension::stress, "rock bulk modulus (Table 4-1), for the DEM specimen").non_negative().def(0.0),
        real("shear", &P::shear, Dimension::stress, "rock shear modulus (Table 4-1), for the DEM specimen").non_negative().def(0.0),
    };
  }
};

struct ElementSettings {
  double step;
  int output_every;
  double frame_stiffness, frame_mass;
  static std::vector<Param<ElementSettings>> spec() {
    using P = ElementSettings;
    return {
        real("step", &P::step, Dimension::length, "largest shear displacement increment").positive().def(1e-5),
        integer("output_every", &P::output_every, 1, "write every n-th increment (each stage's last, and every reversal, stop and restart of the path, always)").min(1),
        real("frame_stiffness", &P::frame_stiffness, Dimension::stiffness,
             "compliant loading frame: spring between the path's load point and the top block, per unit joint "
             "area; 0 = rigid (the joint follows the path exactly)")
            .non_negative()
            .def(0.0),
        real("frame_mass", &P::frame_mass, Dimension::mass_per_area,
             "top-block mass per unit joint area, integrated between the frame spring and the joint (needed "
             "with frame_stiffness > 0)")
            .non_negative()
            .def(0.0),
    };
  }
  void validate() const {
    if (frame_stiffness > 0.0 && !(frame_mass > 0.0)) {
      throw InputError("[element]: frame_stiffness > 0 needs frame_mass > 0 (the top block's mass per unit joint area, "
                       "e.g. \"250 kg/m2\" for a 0.1 m tuff block)");
    }
  }
};

struct DemTable {
  double zone_size, rounding, detection_tolerance, shear_velocity, mass_scaling_dt, dt_safety;
  int history_interval;
  static std::vector<Param<DemTable>> spec() {
    using P = DemTable;
    return {
        real("zone_size", &P::zone_size, Dimension::length, "zone size of the deformable specimen blocks").positive().def(0.01),
        real("rounding", &P::rounding, Dimension::length, "corner rounding length of the blocks").positive().def(5e-4),
        real("detection_tolerance", &P::detection_tolerance, Dimension::length,
             "contacts are found this far beyond the rounding; must exceed the joint's dilation, or points that "
             "come into contact on a dilated joint are missed")
            .positive()
            .max(0.02)
            .def(5e-3),
        real("shear_velocity", &P::shear_velocity, Dimension::velocity,
             "cycles paths run at this speed in the DEM run (0: the stage's own velocity, i.e. the laboratory rate)")
            .non_negative()
            .def(0.0),
        real("mass_scaling_dt", &P::mass_scaling_dt, Dimension::time,
             "scale inertial masses so that this time step is stable (0: real masses)")
            .non_negative()
            .def(0.0),
        real("dt_safety", &P::dt_safety, Dimension::dimensionless, "fraction of the critical time step")
            .positive()
            .max(1.0)
            .def(0.5),
        integer("history_interval", &P::history_interval, 100, "steps between samples of the joint record").min(1),
    };
  }
};

struct StageSettings {
  double normal_stress;
  int normal_control;
  double normal_stiffness;
  int path;
  double amplitude;
  int cycles;
  double velocity;
  bool one_sided;
  double frequency;
  int file_stage;
  static std::vector<Param<StageSettings>> spec() {
    using P = StageSettings;
    return {
        real("normal_stress", &P::normal_stress, Dimension::stress,
             "normal stress of the stage (constant, or initial under constant normal stiffness)")
            .non_negative(),
        choice("normal_control", &P::normal_control, {"stress", "stiffness"}, "stress",
               "stress = constant normal stress; stiffness = constant normal stiffness (spring against dilation)"),
        real("normal_stiffness", &P::normal_stiffness, Dimension::stiffness,
             "spring stiffness for normal_control = \"stiffness\"")
            .non_negative()
            .def(0.0),
        choice("path", &P::path, {"cycles", "sinusoid", "file"}, "",
               "shear displacement history: cycles (amplitude, cycles, velocity, one_sided), sinusoid "
               "(amplitude, frequency, cycles) or file (file, file_stage)"),
        real("amplitude", &P::amplitude, Dimension::length, "shear displacement amplitude").non_negative().def(0.0),
        integer("cycles", &P::cycles, 1, "number of cycles").min(1).max(1e6),
        real("velocity", &P::velocity, Dimension::velocity,
             "shear velocity of the cycles (default: the report's pseudostatic 0.042 mm/s)")
            .positive()
            .def(4.2e-5),
        flag("one_sided", &P::one_sided, false, "cycles go 0 -> +amplitude -> 0 only"),
        real("frequency", &P::frequency, Dimension::frequency, "sinusoid frequency").non_negative().def(0.0),
        integer("file_stage", &P::file_stage, 0,
                "path = file: use the rows of this stage of a measurement file (0 = all rows)")
            .min(0)
            .max(1e6),
    };
  }
};

std::string where_of(const toml::node& n, const std::string& file, const std::string& key) {
  return toml_where(n, file) + " key " + key;
}

// Keys of `t` must be among `allowed`; otherwise an error listing them.
void check_keys(const toml::table& t, const std::string& file, const std::string& path,
                const std::vector<std::string>& allowed) {
  for (const auto& [k, node] : t) {
    if (std::find(allowed.begin(), allowed.end(), k.str()) != allowed.end()) continue;
    throw InputError(where_of(node, file, path.empty() ? std::string(k.str()) : path + "." + std::string(k.str())) +
                     ": unknown key '" + std::string(k.str()) + "'" + (path.empty() ? "" : " in [" + path + "]") +
                     did_you_mean(k.str(), allowed) + "; valid keys: " + join_names(allowed));
  }
}

std::string table_where(const toml::table& t, const std::string& file, const std::string& path) {
  return toml_where(t, file) + " [" + path + "]";
}

// Cross-parameter checks (a law's validate()) do not know where the table was written; add it.
template <class Fn>
auto located(const std::string& file, const std::string& where, Fn&& fn) {
  try {
    return fn();
  } catch (const InputError& e) {
    const std::string m = e.what();
    if (m.rfind(file, 0) == 0) throw;
    throw InputError(where + ": " + m);
  }
}

const toml::table* optional_table(const toml::table& root, const std::string& file, const char* key) {
  const auto* n = root.get(key);
  if (!n) return nullptr;
  const auto* t = n->as_table();
  if (!t) throw InputError(where_of(*n, file, key) + ": '" + key + "' must be a table [" + key + "]");
  return t;
}

}  // namespace

ShearPath read_shear_drive(const std::string& path, int stage, const std::string& where) {
  if (!fs::exists(path)) throw InputError(where + ": shear path file '" + path + "' not found");
  const CsvTable t = read_csv_table(path, {"time_s", "shear_disp_mm"}, "shear drive file");
  const int ct = t.column("time_s"), cu = t.column("shear_disp_mm"), cs = t.column("stage");
  if (stage > 0 && cs < 0)
    throw InputError(where + ": file_stage = " + std::to_string(stage) + " but " + path + " has no 'stage' column");
  std::vector<double> tt, uu;
  for (std::size_t i = 0; i < t.rows.size(); ++i) {
    const auto& r = t.rows[i];
    if (stage > 0 && r[static_cast<std::size_t>(cs)] != stage) continue;
    const double time = r[static_cast<std::size_t>(ct)];
    if (!tt.empty() && time < tt.back())
      throw InputError(path + ":" + std::to_string(t.lines[i]) + ": time going backwards; time_s must not decrease");
    tt.push_back(time);
    uu.push_back(r[static_cast<std::size_t>(cu)] * 1e-3);
  }
  if (tt.size() < 2)
    throw InputError(where + ": fewer than two rows" + (stage > 0 ? " of stage " + std::to_string(stage) : std::string()) +
                     " in " + path + "; a drive needs at least two (time, displacement) points");
  const double t0 = tt.front();
  for (auto& x : tt) x -= t0;
  ShearPath p = ShearPath::table(std::move(tt), std::move(uu));
  // A DEM run reads the file itself as a time history from t = 0: only a whole file starting at 0.
  if (stage == 0 && t0 == 0.0) p.source = path;
  return p;
}

namespace {
// A stage's `file = "..."`: relative to the case file's folder unless absolute.
std::string drive_path(const std::string& case_file, const std::string& written) {
  const fs::path rel(written);
  return (rel.is_absolute() ? rel : fs::path(case_file).parent_path() / rel).string();
}
}  // namespace

ElementStage read_stage(const toml::table& t, const std::string& file, const std::string& path,
                        const std::vector<std::string>& extra_keys) {
  const std::string tw = table_where(t, file, path);
  std::vector<std::string> allowed{"normal_stress", "normal_control", "normal_stiffness", "path",      "amplitude",
                                   "cycles",        "velocity",       "one_sided",        "frequency", "file",
                                   "file_stage"};
  allowed.insert(allowed.end(), extra_keys.begin(), extra_keys.end());
  check_keys(t, file, path, allowed);
  std::vector<std::string_view> skip{"file"};
  for (const auto& k : extra_keys) skip.push_back(k);
  RawValues values;
  for (const auto& [k, v] : t) {
    if (std::find(skip.begin(), skip.end(), k.str()) != skip.end()) continue;
    values[std::string(k.str())] = raw_value(v, file, path + "." + std::string(k.str()));
  }
  const auto s = bind_params<StageSettings>(values, "[[stage]]", tw);
  ElementStage st;
  st.normal_stress = s.normal_stress;
  st.control = s.normal_control == 1 ? NormalControl::constant_stiffness : NormalControl::constant_stress;
  st.normal_stiffness = s.normal_stiffness;
  if (st.control == NormalControl::constant_stiffness && !(s.normal_stiffness > 0.0)) {
    throw InputError(tw + ": normal_control = \"stiffness\" needs normal_stiffness > 0, e.g. \"1 GPa/m\"");
  }
  auto need = [&](bool ok, const std::string& what) {
    if (!ok) throw InputError(tw + ": " + what);
  };
  auto reject = [&](const char* key, const char* why) {
    if (const auto* n = t.get(key)) throw InputError(where_of(*n, file, path + "." + key) + ": " + why);
  };
  switch (s.path) {
    case 0:
      need(s.amplitude > 0.0, "path = \"cycles\" needs amplitude > 0, e.g. amplitude = \"20 mm\"");
      reject("frequency", "frequency belongs to path = \"sinusoid\", not \"cycles\"");
      reject("file", "file belongs to path = \"file\", not \"cycles\"");
      st.path = ShearPath::cycles(s.amplitude, s.cycles, s.velocity, s.one_sided);
      break;
    case 1:
      need(s.amplitude > 0.0, "path = \"sinusoid\" needs amplitude > 0, e.g. amplitude = \"10 mm\"");
      need(s.frequency > 0.0, "path = \"sinusoid\" needs frequency > 0, e.g. frequency = \"1 Hz\"");
      reject("velocity", "velocity belongs to path = \"cycles\"; a sinusoid's speed follows from amplitude and frequency");
      reject("file", "file belongs to path = \"file\", not \"sinusoid\"");
      st.path = ShearPath::sinusoid(s.amplitude, s.frequency, s.cycles);
      break;
    default: {
      const auto* fnode = t.get("file");
      if (!fnode || !fnode->is_string()) {
        throw InputError(tw + ": path = \"file\" needs file = \"<CSV>\": a drive table (time_s, shear_disp_mm) or a "
                              "measurement record");
      }
      reject("amplitude", "amplitude belongs to cycles and sinusoid paths; a file path takes its amplitude from the file");
      st.path = read_shear_drive(drive_path(file, fnode->as_string()->get()), s.file_stage, where_of(*fnode, file, path + ".file"));
    }
  }
  return st;
}

const toml::array& stage_tables(const toml::table& root, const std::string& file) {
  const auto* sn = root.get("stage");
  const auto* sa = sn ? sn->as_array() : nullptr;
  if (!sa || sa->empty() || !sa->is_array_of_tables()) {
    throw InputError(file + ": needs at least one [[stage]] table (normal_stress = \"3 MPa\", path = \"cycles\", ...)");
  }
  return *sa;
}

namespace {

// [specimen]: the name, the joint length and the rock matrix (all three moduli or none).
void read_specimen_table(const toml::table& root, const std::string& file, LabTest& c) {
  if (const auto* t = optional_table(root, file, "specimen")) {
    if (const auto* sp = t->get("name")) {
      if (!sp->is_string()) throw InputError(where_of(*sp, file, "specimen.name") + ": name must be a string");
      c.specimen = sp->as_string()->get();
    }
    const auto s = bind_params<SpecimenSettings>(raw_values(*t, file, "specimen", {"name"}), "[specimen]",
                                                 table_where(*t, file, "specimen"));
    c.joint_length = s.joint_length;
    const int given = (s.density > 0) + (s.bulk > 0) + (s.shear > 0);
    if (given == 3) c.rock = SpecimenRock{s.density, s.bulk, s.shear};
    else if (given != 0)
      throw InputError(table_where(*t, file, "specimen") + ": the rock matrix needs all of density, bulk and shear (> 0), or none");
  }
  if (c.specimen.empty()) c.specimen = fs::path(file).stem().string();
}

// [element] and [dem]: the element driver's and the DEM specimen's settings (defaults if absent).
void read_element_and_dem_tables(const toml::table& root, const std::string& file, LabTest& c) {
  {
    const auto* t = optional_table(root, file, "element");
    const auto s = t ? bind_params<ElementSettings>(raw_values(*t, file, "element"), "[element]", table_where(*t, file, "element"))
                     : bind_params<ElementSettings>({}, "[element]", file);
    c.step = s.step;
    c.output_every = s.output_every;
    c.frame_stiffness = s.frame_stiffness;
    c.frame_mass = s.frame_mass;
  }
  {
    const auto* t = optional_table(root, file, "dem");
    const auto s = t ? bind_params<DemTable>(raw_values(*t, file, "dem"), "[dem]", table_where(*t, file, "dem"))
                     : bind_params<DemTable>({}, "[dem]", file);
    c.dem = DemSettings{s.zone_size,       s.rounding,        s.detection_tolerance, s.shear_velocity,
                        s.mass_scaling_dt, s.dt_safety,       s.history_interval};
  }
}

// [joint] effects: each a name or a table {name = "...", <parameters>}.
std::vector<EffectSpec> read_effects(const toml::table& jt, const std::string& file, LabTest& c) {
  std::vector<EffectSpec> effects;
  if (const auto* en = jt.get("effects")) {
    const auto* arr = en->as_array();
    if (!arr) throw InputError(where_of(*en, file, "joint.effects") + ": effects is a list, e.g. effects = [\"strength_reduction\"]");
    c.effects = *arr;
    for (const auto& e : *arr) {
      EffectSpec es;
      es.where = where_of(e, file, "joint.effects");
      if (const auto* s = e.as_string()) {
        es.name = s->get();
      } else if (const auto* et = e.as_table()) {
        const auto* nm = et->get("name");
        if (!nm || !nm->is_string()) throw InputError(es.where + ": an effect table needs name = \"<effect>\"");
        es.name = nm->as_string()->get();
        es.params = raw_values(*et, file, "joint.effects." + es.name, {"name"});
      } else {
        throw InputError(es.where + ": an effect is a name or a table {name = \"...\", <parameters>}; valid names: " +
                         EffectRegistry::instance().names_joined());
      }
      effects.push_back(std::move(es));
    }
  }
  return effects;
}

// What the [[stage]] tables need of the joint: its parameters (which a stage's params override)
// and its effects.
struct JointTable {
  RawValues law_params;
  std::vector<EffectSpec> effects;
};

// [joint]: the law, its effects and parameters; builds the joint model.
JointTable read_joint_table(const toml::table& root, const std::string& file, LabTest& c) {
  const auto* jn = root.get("joint");
  if (!jn || !jn->is_table()) {
    throw InputError(file + ": missing table [joint] with law = \"<name>\" and [joint.params]; laws: " +
                     JointLawRegistry::instance().names_joined());
  }
  const auto& jt = *jn->as_table();
  check_keys(jt, file, "joint", {"law", "effects", "params"});
  const auto* law_node = jt.get("law");
  if (!law_node || !law_node->is_string()) {
    throw InputError(table_where(jt, file, "joint") + ": 'law' must name a joint law in quotes; valid names: " +
                     JointLawRegistry::instance().names_joined());
  }
  c.law = law_node->as_string()->get();
  const std::string law_where = where_of(*law_node, file, "joint.law");
  JointTable joint;
  joint.effects = read_effects(jt, file, c);
  std::string params_where = table_where(jt, file, "joint");
  if (const auto* pn = jt.get("params")) {
    const auto* pt = pn->as_table();
    if (!pt) throw InputError(where_of(*pn, file, "joint.params") + ": params must be a table [joint.params]");
    joint.law_params = raw_values(*pt, file, "joint.params");
    params_where = table_where(*pt, file, "joint.params");
    c.joint_params = *pt;
  }
  JointLawRegistry::instance().get(c.law, "joint law", law_where);
  c.model = located(file, params_where, [&] { return make_joint_model(c.law, joint.law_params, joint.effects, params_where); });
  return joint;
}

// [[stage]]: each stage's path, and its own joint model where its params override the joint's.
void read_stage_tables(const toml::table& root, const std::string& file, const JointTable& joint, LabTest& c) {
  int index = 0;
  for (const auto& node : stage_tables(root, file)) {
    ++index;
    const auto& t = *node.as_table();
    const std::string path = "stage[" + std::to_string(index) + "]";
    ElementStage st = read_stage(t, file, path, {"params"});
    if (const auto* f = t.get_as<std::string>("file")) c.drive_files.push_back(drive_path(file, f->get()));
    toml::table overrides;
    if (const auto* pn = t.get("params")) {
      const auto* pt = pn->as_table();
      if (!pt) throw InputError(where_of(*pn, file, path + ".params") + ": params must be a table [stage.params]");
      RawValues merged = joint.law_params;
      for (auto& [k, v] : raw_values(*pt, file, path + ".params")) merged[k] = v;
      const std::string pw = table_where(*pt, file, path + ".params");
      c.stage_models.push_back(located(file, pw, [&] { return make_joint_model(c.law, merged, joint.effects, pw); }));
      st.model = c.stage_models.back().get();
      overrides = *pt;
    }
    c.stage_params.push_back(std::move(overrides));
    c.stages.push_back(std::move(st));
  }
}

}  // namespace

LabTest read_lab_test(const std::string& file) {
  const toml::table root = parse_toml_file(file, "case file");
  LabTest c;
  c.file = file;
  // The two dialects: a DEM case ([[blocks]]/[rock_mass], [[stages]]) runs with `rockdem run`;
  // say so rather than "unknown key 'blocks'".
  for (const char* dem_key : {"blocks", "rock_mass", "stages", "joints"})
    if (root.contains(dem_key))
      throw InputError(file + ": this is a DEM case file (it has [" + std::string(dem_key) + "]); run it with `rockdem run " +
                       file + "`. This command takes a laboratory-test case file ([joint] and [[stage]] tables, e.g. "
                       "cases/direct_shear/test09_mohr_coulomb.toml)");
  check_keys(root, file, "", {"title", "specimen", "element", "dem", "joint", "stage"});
  if (const auto* tn = root.get("title")) {
    if (!tn->is_string()) throw InputError(where_of(*tn, file, "title") + ": title must be a string");
    c.title = tn->as_string()->get();
  }
  read_specimen_table(root, file, c);
  read_element_and_dem_tables(root, file, c);
  const JointTable joint = read_joint_table(root, file, c);
  read_stage_tables(root, file, joint, c);
  return c;
}

bool is_lab_test_file(const std::string& path) {
  try {
    const toml::table root = toml::parse_file(path);
    return root.contains("joint") && root.contains("stage") && !root.contains("blocks");
  } catch (const toml::parse_error&) {
    return false;  // the case reader reports the syntax error with its position
  }
}

ElementRun run_element_test(const LabTest& c) {
  ElementOptions opt;
  opt.max_step = c.step;
  opt.length = c.joint_length;
  opt.output_every = c.output_every;
  opt.frame_stiffness = c.frame_stiffness;
  opt.frame_mass = c.frame_mass;
  ElementDriver driver(*c.model, opt);
  ElementRun run;
  run.record.metadata = {{"specimen", c.specimen},
                         {"joint_length_m", round_trip_text(c.joint_length)},
                         {"source", "rockdem"},
                         {"model", "element"},
                         {"rockdem_version", ROCKDEM_VERSION},
                         {"case", c.file},
                         {"joint_model", c.model->description()}};
  const auto t0 = std::chrono::steady_clock::now();
  driver.run(c.stages, run.record, 1);
  run.wall_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  run.increments = driver.steps();
  run.unconverged = driver.unconverged_steps();
  return run;
}

}  // namespace rockdem
