// `rockdem element CASE.toml [--out FILE.csv]`: drives one joint point through the stages of a
// direct shear test (see framework/mechanics/element_driver.hpp) and writes the result in the
// measurement format. The case file:
//   [element]                      optional: specimen (text), joint_length, step, output_every
//   [joint]                        law = "<name>", effects = ["<name>" | {name = "...", <params>}]
//   [joint.params]                 the law's parameters, quantities with units ("38 deg")
//   [[stage]]                      one per normal-stress stage, in test order: normal_stress,
//                                  normal_control, normal_stiffness, path = cycles | sinusoid |
//                                  file and its keys; optional [stage.params] overrides
// Every mistake is an InputError naming file:line and key, what is wrong and what is valid.
#include <charconv>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <numbers>
#include <set>

#include <toml++/toml.h>

#include "framework/app/command.hpp"
#include "framework/core/error.hpp"
#include "framework/io/measurement_csv.hpp"
#include "framework/io/toml_values.hpp"
#include "framework/mechanics/element_driver.hpp"
#include "rockdem_version.hpp"

namespace rockdem {
namespace {

namespace fs = std::filesystem;

struct ElementSettings {
  double joint_length;
  double step;
  int output_every;
  static std::vector<Param<ElementSettings>> spec() {
    using P = ElementSettings;
    return {
        real("joint_length", &P::joint_length, Dimension::length,
             "joint length of the specimen, handed to the law as the contact length")
            .positive()
            .def(1.0),
        real("step", &P::step, Dimension::length, "largest shear displacement increment").positive().def(1e-5),
        integer("output_every", &P::output_every, 1, "write every n-th increment (each stage's last always)").min(1),
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
                "path = file: use the rows of this stage of the measurement file (0 = all rows)")
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
                std::initializer_list<std::string_view> allowed) {
  for (const auto& [k, node] : t) {
    bool ok = false;
    for (auto a : allowed) ok = ok || k.str() == a;
    if (!ok) {
      std::string valid;
      for (auto a : allowed) {
        if (!valid.empty()) valid += ", ";
        valid += a;
      }
      throw InputError(where_of(node, file, path.empty() ? std::string(k.str()) : path + "." + std::string(k.str())) +
                       ": unknown key '" + std::string(k.str()) + "' in [" + path + "]; valid keys: " + valid);
    }
  }
}

std::string table_where(const toml::table& t, const std::string& file, const std::string& path) {
  return toml_where(t, file) + " [" + path + "]";
}

std::string shortest(double v) {
  char buf[64];
  auto [end, ec] = std::to_chars(buf, buf + sizeof(buf), v);
  (void)ec;
  return std::string(buf, end);
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

struct ElementCase {
  std::string file;
  std::string specimen;
  ElementSettings settings{};
  std::unique_ptr<JointModel> model;
  std::vector<std::unique_ptr<JointModel>> stage_models;
  std::vector<ElementStage> stages;
};

ElementCase read_case(const std::string& file) {
  if (!fs::exists(file)) throw InputError(file + ": case file not found");
  toml::table root;
  try {
    root = toml::parse_file(file);
  } catch (const toml::parse_error& e) {
    throw InputError(file + ":" + std::to_string(e.source().begin.line) + ":" +
                     std::to_string(e.source().begin.column) + ": TOML syntax error: " + std::string(e.description()));
  }
  ElementCase c;
  c.file = file;
  check_keys(root, file, "", {"element", "joint", "stage"});

  // [element]
  if (const auto* node = root.get("element")) {
    const auto* t = node->as_table();
    if (!t) throw InputError(where_of(*node, file, "element") + ": 'element' must be a table [element]");
    check_keys(*t, file, "element", {"specimen", "joint_length", "step", "output_every"});
    if (const auto* sp = t->get("specimen")) {
      if (!sp->is_string()) throw InputError(where_of(*sp, file, "element.specimen") + ": specimen must be a string");
      c.specimen = sp->as_string()->get();
    }
    c.settings = bind_params<ElementSettings>(raw_values(*t, file, "element", {"specimen"}), "[element]",
                                              table_where(*t, file, "element"));
  } else {
    c.settings = bind_params<ElementSettings>({}, "[element]", file);
  }
  if (c.specimen.empty()) c.specimen = fs::path(file).stem().string();

  // [joint]
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
  const std::string law = law_node->as_string()->get();
  const std::string law_where = where_of(*law_node, file, "joint.law");
  std::vector<EffectSpec> effects;
  if (const auto* en = jt.get("effects")) {
    const auto* arr = en->as_array();
    if (!arr) throw InputError(where_of(*en, file, "joint.effects") + ": effects is a list, e.g. effects = [\"strength_reduction\"]");
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
  RawValues law_params;
  std::string params_where = table_where(jt, file, "joint");
  if (const auto* pn = jt.get("params")) {
    const auto* pt = pn->as_table();
    if (!pt) throw InputError(where_of(*pn, file, "joint.params") + ": params must be a table [joint.params]");
    law_params = raw_values(*pt, file, "joint.params");
    params_where = table_where(*pt, file, "joint.params");
  }
  JointLawRegistry::instance().get(law, "joint law", law_where);
  c.model = located(file, params_where, [&] { return make_joint_model(law, law_params, effects, params_where); });

  // [[stage]]
  const auto* sn = root.get("stage");
  const auto* sa = sn ? sn->as_array() : nullptr;
  if (!sa || sa->empty() || !sa->is_array_of_tables()) {
    throw InputError(file + ": needs at least one [[stage]] table (normal_stress = \"3 MPa\", path = \"cycles\", ...)");
  }
  int index = 0;
  for (const auto& node : *sa) {
    ++index;
    const auto& t = *node.as_table();
    const std::string path = "stage[" + std::to_string(index) + "]";
    const std::string tw = table_where(t, file, path);
    check_keys(t, file, path,
               {"normal_stress", "normal_control", "normal_stiffness", "path", "amplitude", "cycles", "velocity",
                "one_sided", "frequency", "file", "file_stage", "params"});
    const auto s = bind_params<StageSettings>(raw_values(t, file, path, {"file", "params"}), "[[stage]]", tw);
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
          throw InputError(tw + ": path = \"file\" needs file = \"<measurement CSV>\" (time_s and shear_disp_mm are used)");
        }
        const fs::path rel(fnode->as_string()->get());
        const fs::path full = rel.is_absolute() ? rel : fs::path(file).parent_path() / rel;
        if (!fs::exists(full)) {
          throw InputError(where_of(*fnode, file, path + ".file") + ": shear path file '" + full.string() + "' not found");
        }
        const MeasurementFile mf = read_measurement_csv(full.string());
        std::vector<double> tt, uu;
        for (const auto& row : mf.rows) {
          if (s.file_stage > 0 && row.stage != s.file_stage) continue;
          tt.push_back(row.time_s);
          uu.push_back(row.shear_disp_mm * 1e-3);
        }
        if (tt.empty()) {
          throw InputError(where_of(*fnode, file, path + ".file") + ": no rows" +
                           (s.file_stage > 0 ? " of stage " + std::to_string(s.file_stage) : std::string()) + " in " +
                           full.string());
        }
        const double t0 = tt.front();
        for (auto& x : tt) x -= t0;
        st.path = ShearPath::table(std::move(tt), std::move(uu));
      }
    }
    if (const auto* pn = t.get("params")) {
      const auto* pt = pn->as_table();
      if (!pt) throw InputError(where_of(*pn, file, path + ".params") + ": params must be a table [stage.params]");
      RawValues merged = law_params;
      for (auto& [k, v] : raw_values(*pt, file, path + ".params")) merged[k] = v;
      const std::string pw = table_where(*pt, file, path + ".params");
      c.stage_models.push_back(located(file, pw, [&] { return make_joint_model(law, merged, effects, pw); }));
      st.model = c.stage_models.back().get();
    }
    c.stages.push_back(std::move(st));
  }
  return c;
}

const CommandRegistrar reg{Command{
    "element", "drive one joint point through a direct-shear path (element test) and write a measurement CSV", false,
    [](CLI::App& sub) {
      auto file = std::make_shared<std::string>();
      auto out = std::make_shared<std::string>();
      auto quiet = std::make_shared<bool>(false);
      sub.add_option("case", *file, "element case file (TOML), e.g. cases/element/test09_mohr_coulomb.toml")->required();
      sub.add_option("--out", *out, "output CSV (default: <case name>.csv in the current folder)");
      sub.add_flag("--quiet", *quiet, "no summary on standard output");
      return [file, out, quiet]() -> int {
        ElementCase c = read_case(*file);
        ElementOptions opt;
        opt.max_step = c.settings.step;
        opt.length = c.settings.joint_length;
        opt.output_every = c.settings.output_every;
        ElementDriver driver(*c.model, opt);
        MeasurementFile mf;
        mf.metadata = {{"specimen", c.specimen},
                       {"joint_length_m", shortest(c.settings.joint_length)},
                       {"source", "rockdem"},
                       {"rockdem_version", ROCKDEM_VERSION},
                       {"case", *file},
                       {"joint_model", c.model->description()}};
        const auto t0 = std::chrono::steady_clock::now();
        driver.run(c.stages, mf, 1);
        const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
        const std::string path = out->empty() ? fs::path(*file).stem().string() + ".csv" : *out;
        write_measurement_csv(path, mf);
        if (!*quiet) {
          std::printf("%s: %s, %zu stage(s), %ld increments in %.1f ms -> %s (%zu rows)\n", c.specimen.c_str(),
                      c.model->description().c_str(), c.stages.size(), driver.steps(), ms, path.c_str(),
                      mf.rows.size());
          for (std::size_t si = 0; si < c.stages.size(); ++si) {
            double tmax = -1e300, tmin = 1e300, dmax = -1e300;
            for (const auto& r : mf.rows) {
              if (r.stage != static_cast<int>(si) + 1) continue;
              tmax = std::max(tmax, r.shear_stress_MPa);
              tmin = std::min(tmin, r.shear_stress_MPa);
              dmax = std::max(dmax, r.normal_disp_mm);
            }
            std::printf("  stage %zu: sigma_n %.3f MPa, shear stress %+.4f .. %+.4f MPa, max normal disp %.4f mm\n",
                        si + 1, c.stages[si].normal_stress / 1e6, tmin, tmax, dmax);
          }
          if (driver.unconverged_steps() > 0) {
            std::printf("  warning: %ld increments did not meet the normal-stress tolerance\n", driver.unconverged_steps());
          }
        }
        return 0;
      };
    }}};

}  // namespace
}  // namespace rockdem
