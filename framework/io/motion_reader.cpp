// [[motions]] of a case file (keys in docs/case-files.md): a recorded ground motion and how it
// is processed into a model's seismic input. The record itself is read, processed and checked
// against the mesh by the case builder, which knows the model.
#include <filesystem>

#include "framework/io/case_reader.hpp"
#include "framework/io/toml_table.hpp"

namespace rockdem {
namespace {

int whole_number(const TomlTable& t, const std::string& key, int def, int lo, int hi) {
  const toml::node* n = t.t.get(key);
  if (!n) return def;
  const auto* i = n->as_integer();
  if (!i || i->get() < lo || i->get() > hi)
    throw InputError(t.key_at(*n, key) + ": expected a whole number from " + std::to_string(lo) + " to " + std::to_string(hi));
  return static_cast<int>(i->get());
}

std::string choice(const TomlTable& t, const std::string& key, const std::string& def,
                   std::initializer_list<std::string_view> valid, const std::string& meaning) {
  const std::string v = t.text(key, def);
  if (std::find(valid.begin(), valid.end(), v) == valid.end())
    throw InputError(t.key_at(*t.t.get(key), key) + ": unknown " + key + " '" + v + "'; valid: " + join_names(valid) +
                     (meaning.empty() ? std::string() : " (" + meaning + ")"));
  return v;
}

void read_filter(const TomlTable& t, MotionSpec& m) {
  const toml::node* n = t.t.get("filter");
  if (!n) return;
  const auto* ft = n->as_table();
  if (!ft) throw InputError(t.key_at(*n, "filter") + ": expected a table, e.g. filter = { low = \"0.1 Hz\", high = \"15 Hz\", order = 4 }");
  const TomlTable f{*ft, t.file, t.path + ".filter"};
  f.only({"low", "high", "order"});
  m.filter_where = t.key_at(*n, "filter");
  m.processing.f_low = f.at_least("low", Dimension::frequency, 0.0, true);
  m.processing.f_high = f.at_least("high", Dimension::frequency, 0.0, true);
  m.processing.order = whole_number(f, "order", 4, 1, 8);
}

void read_scaling(const TomlTable& t, MotionSpec& m) {
  int given = 0;
  if (t.t.contains("scale")) {
    m.scaling = {seismic::MotionScaling::Kind::factor, t.at_least("scale", Dimension::dimensionless, std::nullopt)};
    ++given;
  }
  if (t.t.contains("pga")) {
    m.scaling = {seismic::MotionScaling::Kind::pga, t.at_least("pga", Dimension::acceleration, std::nullopt)};
    ++given;
  }
  if (t.t.contains("pgv")) {
    m.scaling = {seismic::MotionScaling::Kind::pgv, t.at_least("pgv", Dimension::velocity, std::nullopt)};
    ++given;
  }
  if (given > 1) throw InputError(t.here() + ": give one of scale, pga and pgv");
}

}  // namespace

MotionSpec CaseReader::motion(const toml::table& tt) const {
  const TomlTable t{tt, file_, "motions"};
  t.only({"name", "file", "format", "unit", "column", "time_column", "dt", "type", "direction", "window", "baseline", "taper",
          "pad", "filter", "displacement_baseline", "scale", "pga", "pgv", "above_mesh", "zones_per_wavelength"});
  MotionSpec m;
  m.name = t.text("name");
  if (m.name.empty()) throw InputError(t.key_at(t.required("name"), "name") + ": must not be empty");
  m.where = t.here() + " '" + m.name + "'";
  const std::string file = t.text("file");
  m.file_where = t.key_at(t.required("file"), "file");
  m.file = std::filesystem::path(file).is_absolute() ? file : (std::filesystem::path(base_dir_) / file).string();
  m.format = choice(t, "format", "auto", {"auto", "columns", "csv", "peer_at2"},
                    "auto: peer_at2 for .AT2 files, csv for .csv, else whitespace columns");
  if (t.t.contains("unit")) {
    try {
      m.layout.unit = seismic::parse_acceleration_unit(t.text("unit"));
    } catch (const InputError& e) {
      throw InputError(t.key_at(*t.t.get("unit"), "unit") + ": " + e.what());
    }
  } else {
    m.layout.unit = seismic::parse_acceleration_unit("g");
  }
  m.layout.column = t.t.contains("column") ? (t.t.get("column")->is_integer()
                                                  ? std::to_string(t.t.get("column")->as_integer()->get())
                                                  : t.text("column"))
                                           : std::string();
  m.layout.time_column = whole_number(t, "time_column", t.t.contains("dt") ? 0 : 1, 0, 1000);
  if (t.t.contains("dt")) m.layout.dt = t.at_least("dt", Dimension::time, std::nullopt);
  m.type = [&] {
    const std::string s = choice(t, "type", "outcrop", {"outcrop", "incident", "within"},
                                 "outcrop: recorded at the surface, twice the upgoing wave; incident: the upgoing wave; "
                                 "within: recorded at depth, for a rigid base only");
    return s == "outcrop" ? seismic::MotionType::outcrop : s == "incident" ? seismic::MotionType::incident : seismic::MotionType::within;
  }();
  m.direction = choice(t, "direction", "x", {"x", "y"}, "x: horizontal motion, y: vertical") == "x" ? 0 : 1;
  if (const toml::node* n = t.t.get("window")) {
    const auto* a = n->as_array();
    if (!a || a->size() != 2) throw InputError(t.key_at(*n, "window") + ": expected [start, end] with units, e.g. [\"2 s\", \"22 s\"]");
    m.processing.start = t.value(*a->get(0), "window", Dimension::time);
    m.processing.end = t.value(*a->get(1), "window", Dimension::time);
    if (!(m.processing.start >= 0.0 && m.processing.end > m.processing.start))
      throw InputError(t.key_at(*n, "window") + ": needs 0 <= start < end");
  }
  m.processing.acc_baseline_degree = whole_number(t, "baseline", 1, -1, 10);
  m.processing.taper = t.at_least("taper", Dimension::time, 0.0, true);
  m.processing.pad = t.at_least("pad", Dimension::time, 0.0, true);
  read_filter(t, m);
  m.processing.disp_baseline_degree = whole_number(t, "displacement_baseline", 0, 0, 10);
  if (m.processing.disp_baseline_degree == 1)
    throw InputError(t.key_at(*t.t.get("displacement_baseline"), "displacement_baseline") +
                     ": valid: 0 (none) or 2..10 (powers 2..degree, so that the motion still starts at rest)");
  read_scaling(t, m);
  m.refuse_above_mesh = choice(t, "above_mesh", "filter", {"filter", "refuse"},
                               "what to do with a record carrying frequencies the zones cannot: low-pass it at the "
                               "mesh limit, or stop") == "refuse";
  m.zones_per_wavelength = t.at_least("zones_per_wavelength", Dimension::dimensionless, 10.0);
  if (m.zones_per_wavelength < 4.0)
    throw InputError(t.key_at(*t.t.get("zones_per_wavelength"), "zones_per_wavelength") +
                     ": below 4 zones per wavelength a wave is not carried at all; 8 to 10 is the usual rule");
  return m;
}

}  // namespace rockdem
