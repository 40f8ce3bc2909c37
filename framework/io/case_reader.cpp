#include "framework/io/case_reader.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "framework/core/did_you_mean.hpp"
#include "framework/core/error.hpp"
#include "framework/core/names.hpp"
#include "framework/core/units.hpp"
#include "framework/io/calibration_file.hpp"
#include "framework/io/measurement_csv.hpp"
#include "framework/io/toml_values.hpp"
#include "framework/mechanics/history_quantities.hpp"

namespace rockdem {
namespace {

namespace fs = std::filesystem;

// Reading context: the file name for messages and the folder relative paths start from. It
// refers to the CaseReader's strings (each of its methods makes one on entry), so making one
// copies nothing.
struct Reader {
  const std::string& file;
  const std::string& base_dir;

  std::string at(const toml::node& n, const std::string& key) const {
    // A value the command line put in (rockdem run --excavate, --seed) has no line in the file.
    if (n.source().begin.line == 0) return file + " key '" + key + "' (a value not read from the file: given on the command line, or made by rockdem)";
    return file + ":" + std::to_string(n.source().begin.line) + " key '" + key + "'";
  }
  std::string at_table(const toml::table& t, const std::string& path) const {
    return file + ":" + std::to_string(t.source().begin.line) + " [" + path + "]";
  }

  void check_keys(const toml::table& t, const std::string& path, std::initializer_list<std::string_view> allowed) const {
    check_keys_in(t, path, allowed);
  }
  template <class Names>
  void check_keys_in(const toml::table& t, const std::string& path, const Names& allowed) const {
    for (auto&& [k, v] : t) {
      if (std::find(allowed.begin(), allowed.end(), k.str()) == allowed.end()) {
        throw InputError(at(v, path + "." + std::string(k.str())) + ": unknown key '" + std::string(k.str()) +
                         "' in [" + path + "]" + did_you_mean(k.str(), allowed) +
                         "; valid keys: " + join_names(allowed));
      }
    }
  }

  const toml::node& need(const toml::table& t, const std::string& key, const std::string& path) const {
    const toml::node* n = t.get(key);
    if (!n) throw InputError(at_table(t, path) + ": missing required key '" + key + "'");
    return *n;
  }

  std::string str(const toml::node& n, const std::string& key) const {
    if (const auto* s = n.as_string()) return s->get();
    throw InputError(at(n, key) + ": expected a string");
  }
  std::string str(const toml::table& t, const std::string& key, const std::string& path,
                  std::optional<std::string> def = std::nullopt) const {
    const toml::node* n = t.get(key);
    if (!n) {
      if (def) return *def;
      throw InputError(at_table(t, path) + ": missing required key '" + key + "'");
    }
    return str(*n, path + "." + key);
  }

  double quantity(const toml::node& n, Dimension d, const std::string& key) const {
    return quantity_value(raw_value(n, file, key), d, "value");
  }
  double quantity(const toml::table& t, const std::string& key, Dimension d, const std::string& path,
                  std::optional<double> def = std::nullopt) const {
    const toml::node* n = t.get(key);
    if (!n) {
      if (def) return *def;
      throw InputError(at_table(t, path) + ": missing required key '" + key + "' (a " +
                       std::string(dimension_name(d)) + (d == Dimension::dimensionless ? "" : ", e.g. \"1 " + std::string(si_unit(d)) + "\"") + ")");
    }
    return quantity(*n, d, path + "." + key);
  }
  double positive(const toml::table& t, const std::string& key, Dimension d, const std::string& path,
                  std::optional<double> def = std::nullopt) const {
    const double v = quantity(t, key, d, path, def);
    if (!(v > 0.0))
      throw InputError((t.get(key) ? at(*t.get(key), path + "." + key) : at_table(t, path)) + ": '" + key +
                       "' must be positive, got " + format_quantity(v, d));
    return v;
  }
  long integer(const toml::table& t, const std::string& key, const std::string& path, long def) const {
    const toml::node* n = t.get(key);
    if (!n) return def;
    if (const auto* i = n->as_integer()) return static_cast<long>(i->get());
    throw InputError(at(*n, path + "." + key) + ": expected an integer");
  }
  bool boolean(const toml::table& t, const std::string& key, const std::string& path, bool def) const {
    const toml::node* n = t.get(key);
    if (!n) return def;
    if (const auto* b = n->as_boolean()) return b->get();
    throw InputError(at(*n, path + "." + key) + ": expected true or false");
  }
  const toml::array* array(const toml::table& t, const std::string& key) const {
    const toml::node* n = t.get(key);
    if (!n) return nullptr;
    if (const auto* a = n->as_array()) return a;
    throw InputError(at(*n, key) + ": expected an array");
  }
  std::vector<const toml::table*> tables(const toml::table& root, const std::string& key) const {
    std::vector<const toml::table*> out;
    const toml::node* n = root.get(key);
    if (!n) return out;
    const auto* arr = n->as_array();
    if (!arr) throw InputError(at(*n, key) + ": expected an array of tables, written [[" + key + "]]");
    for (const auto& e : *arr) {
      const auto* t = e.as_table();
      if (!t) throw InputError(at(e, key) + ": expected a table, written [[" + key + "]]");
      out.push_back(t);
    }
    return out;
  }
  std::string resolve(const std::string& p) const {
    fs::path path(p);
    return path.is_absolute() ? p : (fs::path(base_dir) / path).string();
  }

  // {file = {...}}: a two-column file, or named columns of a CSV table.
  TimeFunction file_function(const toml::table& body, Dimension d, const std::string& path) const {
    check_keys(body, path, {"path", "time_unit", "value_unit", "holds", "time_column", "value_column"});
    const std::string holds = str(body, "holds", path, std::string("velocity"));
    if (holds != "velocity" && holds != "displacement")
      throw InputError(at(body, path + ".holds") + ": must be 'velocity' or 'displacement', not '" + holds + "'");
    const Dimension vd = holds == "displacement" ? Dimension::length : d;
    const double ts = parse_quantity("1 " + str(body, "time_unit", path, std::string("s")), Dimension::time);
    const std::string vu = str(body, "value_unit", path);
    double vs = 0.0;
    try {
      vs = parse_quantity("1 " + vu, vd);
    } catch (const InputError& e) {
      throw InputError(at(body, path + ".value_unit") + ": " + e.what());
    }
    const std::string file_path = resolve(str(body, "path", path));
    if (!fs::exists(file_path))
      throw InputError(at(body, path + ".path") + ": data file '" + file_path + "' does not exist");
    // With column names the file is a CSV table with a header (e.g. a drive table time_s,
    // shear_disp_mm, or a measurement record); without, two bare columns.
    const bool named = body.contains("time_column") || body.contains("value_column");
    if (!named) return TimeFunction::from_file(file_path, ts, vs, holds == "displacement");
    const std::string tc = str(body, "time_column", path), vc = str(body, "value_column", path);
    const CsvTable tab = read_csv_table(file_path, {tc, vc}, "time-history table");
    std::vector<double> tt, vv;
    for (const auto& row : tab.rows) {
      tt.push_back(row[static_cast<std::size_t>(tab.column(tc))] * ts);
      vv.push_back(row[static_cast<std::size_t>(tab.column(vc))] * vs);
    }
    return TimeFunction::from_samples(std::move(tt), std::move(vv), holds == "displacement", file_path);
  }

  // {expression = {...}}: a formula of t in the given unit.
  TimeFunction expression_function(const toml::table& body, Dimension d, const std::string& path) const {
    check_keys(body, path, {"value", "unit"});
    const std::string unit = str(body, "unit", path);
    double scale = 0.0;
    try {
      scale = parse_quantity("1 " + unit, d);
    } catch (const InputError& e) {
      throw InputError(at(body, path + ".unit") + ": " + e.what());
    }
    try {
      const std::string expr = str(body, "value", path);
      return TimeFunction::expression(scale == 1.0 ? expr : "(" + expr + ")*" + std::to_string(scale));
    } catch (const InputError& e) {
      throw InputError(at(body, path + ".value") + ": " + e.what());
    }
  }

  // A time function: a constant with unit, or a table {cycles|sine|file|expression = ...}.
  TimeFunction time_function(const toml::node& n, Dimension d, const std::string& key) const {
    if (n.is_string() || n.is_number()) return TimeFunction::constant(quantity(n, d, key));
    const auto* t = n.as_table();
    if (!t || t->size() != 1)
      throw InputError(at(n, key) + ": expected a value with unit or one of {cycles = {...}}, {sine = {...}}, "
                       "{file = {...}}, {expression = {...}}");
    const auto first = t->begin();
    const std::string kind(first->first.str());
    const toml::node& v = first->second;
    const auto* body = v.as_table();
    if (!body) throw InputError(at(v, key + "." + kind) + ": expected a table");
    const std::string path = key + "." + kind;
    if ((kind == "cycles" || kind == "sine") && d != Dimension::velocity)
      throw InputError(at(v, path) + ": '" + kind + "' describes a displacement path and drives velocities; for a " +
                       std::string(dimension_name(d)) + " use a constant, file or expression");
    if (kind == "cycles") {
      check_keys(*body, path, {"amplitude", "speed", "number", "one_sided"});
      return TimeFunction::cycles(positive(*body, "amplitude", Dimension::length, path),
                                  positive(*body, "speed", Dimension::velocity, path),
                                  static_cast<int>(integer(*body, "number", path, 1)),
                                  boolean(*body, "one_sided", path, false));
    }
    if (kind == "sine") {
      check_keys(*body, path, {"amplitude", "frequency", "cycles"});
      return TimeFunction::sine(positive(*body, "amplitude", Dimension::length, path),
                                positive(*body, "frequency", Dimension::frequency, path),
                                positive(*body, "cycles", Dimension::dimensionless, path));
    }
    if (kind == "file") return file_function(*body, d, path);
    if (kind == "expression") return expression_function(*body, d, path);
    throw InputError(at(v, path) + ": unknown time history '" + kind + "'; valid: cycles, sine, file, expression");
  }
};

Polygon read_points(const Reader& r, const toml::array& a, const std::string& key) {
  Polygon p;
  for (const auto& e : a) {
    const auto* xy = e.as_array();
    if (!xy || xy->size() != 2) throw InputError(r.at(e, key) + ": each vertex is [x, y] with units, e.g. [\"0 mm\", \"10 mm\"]");
    p.emplace_back(r.quantity(*xy->get(0), Dimension::length, key), r.quantity(*xy->get(1), Dimension::length, key));
  }
  if (p.size() < 3) throw InputError(r.at(a, key) + ": a polygon needs at least 3 vertices");
  return p;
}

Damping read_damping(const Reader& r, const toml::table& t, const std::string& path) {
  const std::string kind = r.str(t, "damping", path, std::string("local"));
  if (kind == "local") {
    Damping d;
    d.local_alpha = r.quantity(t, "local_damping", Dimension::dimensionless, path, 0.8);
    return d;
  }
  if (kind == "none") {
    Damping d;
    d.kind = Damping::Kind::none;
    return d;
  }
  if (kind == "rayleigh") {
    const double xi = r.quantity(t, "damping_ratio", Dimension::dimensionless, path);
    if (xi < 0.0 || xi >= 1.0)
      throw InputError(r.at(*t.get("damping_ratio"), path + ".damping_ratio") + ": must be in [0, 1), got " + std::to_string(xi));
    // Which terms: both (default), or one of them alone with the fraction exactly at one frequency
    // (FLAC's and UDEC's mass- and stiffness-only options). The stiffness term shortens the stable
    // step (docs/engine.md), which small zones of a rock mass cannot afford.
    const std::string terms = r.str(t, "rayleigh_terms", path, std::string("both"));
    if (terms != "both") {
      const std::string where = r.at(*t.get("rayleigh_terms"), path + ".rayleigh_terms");
      const std::vector<std::string> valid{"both", "mass", "stiffness"};
      if (terms != "mass" && terms != "stiffness")
        throw InputError(where + ": unknown '" + terms + "'" + did_you_mean(terms, valid) +
                         "; valid: both, mass, stiffness");
      if (const auto* band = t.get("damping_frequency"); band && band->is_array())
        throw InputError(r.at(*band, path + ".damping_frequency") + ": rayleigh_terms = \"" + terms +
                         "\" damps by the fraction at one frequency; give one, e.g. \"5 Hz\" (a band needs both terms)");
      const double f = r.positive(t, "damping_frequency", Dimension::frequency, path);
      return terms == "mass" ? Damping::rayleigh_mass(xi, f) : Damping::rayleigh_stiffness(xi, f);
    }
    // One frequency: the fraction at its minimum there; two: the same fraction at both ends of a
    // band (below it at frequencies between them).
    if (const auto* band = t.get("damping_frequency"); band && band->is_array()) {
      const auto& a = *band->as_array();
      const std::string where = r.at(*band, path + ".damping_frequency");
      if (a.size() != 2) throw InputError(where + ": expected one frequency or a band of two, e.g. [\"1 Hz\", \"10 Hz\"]");
      const double f1 = r.quantity(*a.get(0), Dimension::frequency, path + ".damping_frequency");
      const double f2 = r.quantity(*a.get(1), Dimension::frequency, path + ".damping_frequency");
      if (!(f1 > 0.0 && f2 > f1 && std::isfinite(f2)))
        throw InputError(where + ": the band needs 0 < f1 < f2");
      return Damping::rayleigh_band(xi, f1, f2);
    }
    const double f = r.positive(t, "damping_frequency", Dimension::frequency, path);
    return Damping::rayleigh(xi, f);
  }
  throw InputError(r.at(*t.get("damping"), path + ".damping") + ": unknown damping '" + kind +
                   "'; valid: local, rayleigh, none");
}


// [[joints]] effects = ["name", {name = "...", <parameters>}, ...]
std::vector<EffectSpec> read_effects(const Reader& r, const toml::table& t, const std::string& path) {
  std::vector<EffectSpec> effects;
  const auto* ea = r.array(t, "effects");
  if (!ea) return effects;
  for (const auto& e : *ea) {
    EffectSpec es;
    es.where = r.at(e, path + ".effects");
    if (const auto* s = e.as_string()) {
      es.name = s->get();
    } else if (const auto* et = e.as_table()) {
      es.name = r.str(*et, "name", path + ".effects");
      es.params = raw_values(*et, r.file, path + ".effects." + es.name, {"name"});
    } else {
      throw InputError(es.where + ": an effect is a name or a table {name = ..., <parameters>}");
    }
    effects.push_back(std::move(es));
  }
  return effects;
}

// [[blocks]] rectangle = [x0, y0, width, height] or polygon = [[x, y], ...]
void read_shape(const Reader& r, const toml::table& t, const std::string& path, BlockSpec& b) {
  if (t.contains("rectangle")) {
    const auto* a = r.array(t, "rectangle");
    b.shape_where = r.at(*a, path + ".rectangle");
    if (a->size() != 4) throw InputError(b.shape_where + ": expected [x0, y0, width, height] with units");
    const auto length = [&](std::size_t i) { return r.quantity(*a->get(i), Dimension::length, path + ".rectangle"); };
    b.rectangle = BlockSpec::Rectangle{length(0), length(1), length(2), length(3)};
  } else if (const auto* a = r.array(t, "polygon")) {
    b.shape_where = r.at(*a, path + ".polygon");
    b.polygon = read_points(r, *a, path + ".polygon");
  } else {
    throw InputError(r.at_table(t, path) +
                     ": give the block's shape as rectangle = [x0, y0, width, height] or polygon = [[x, y], ...]");
  }
}

// [[blocks]] of deformable blocks: zones = [nx, ny], or zone_size and mesh.
void read_mesh(const Reader& r, const toml::table& t, const std::string& path, BlockSpec& b) {
  if (const auto* z = r.array(t, "zones")) {
    b.zones_where = r.at(*z, path + ".zones");
    const auto nx = z->size() == 2 ? z->get(0)->value<int64_t>() : std::nullopt;
    const auto ny = z->size() == 2 ? z->get(1)->value<int64_t>() : std::nullopt;
    if (!nx || !ny || *nx < 1 || *ny < 1) throw InputError(b.zones_where + ": expected [nx, ny], positive integers");
    b.zones = std::array<int, 2>{static_cast<int>(*nx), static_cast<int>(*ny)};
    return;
  }
  b.zone_size = r.positive(t, "zone_size", Dimension::length, path);
  const std::string kind = r.str(t, "mesh", path, std::string(b.rectangle ? "structured" : "unstructured"));
  if (const toml::node* n = t.get("mesh")) b.mesh_where = r.at(*n, path + ".mesh");
  if (kind != "structured" && kind != "unstructured")
    throw InputError(b.mesh_where + ": unknown mesh '" + kind + "'; valid: structured (rectangles), unstructured");
  b.mesh = kind == "structured" ? BlockSpec::Mesh::structured : BlockSpec::Mesh::unstructured;
}

// motion = "name" or ["h", "v"], and its scaling for the stage: motion_scale, pga or pgv.
void read_stage_motions(const Reader& r, const toml::table& t, const std::string& path, StageInput& in) {
  if (const toml::node* n = t.get("motion")) {
    if (const auto* a = n->as_array()) {
      for (const auto& e : *a) {
        in.motions.push_back(r.str(e, path + ".motion"));
        in.motion_wheres.push_back(r.at(e, path + ".motion"));
      }
    } else {
      in.motions.push_back(r.str(*n, path + ".motion"));
      in.motion_wheres.push_back(r.at(*n, path + ".motion"));
    }
    if (in.motions.empty()) throw InputError(r.at(*n, path + ".motion") + ": name at least one [[motions]] entry");
  }
  using Kind = seismic::MotionScaling::Kind;
  int given = 0;
  for (auto [key, kind, dim] : {std::tuple{"motion_scale", Kind::factor, Dimension::dimensionless},
                                std::tuple{"pga", Kind::pga, Dimension::acceleration},
                                std::tuple{"pgv", Kind::pgv, Dimension::velocity}}) {
    if (!t.contains(key)) continue;
    const std::string where = r.at(*t.get(key), path + "." + key);
    if (in.motions.empty()) throw InputError(where + ": the stage plays no motion (add motion = \"...\")");
    if (++given > 1) throw InputError(where + ": give one of motion_scale, pga and pgv");
    in.motion_scaling = {kind, r.positive(t, key, dim, path)};
    in.motion_scaling_where = where;
  }
}

// A [[boundary]] key of a condition kind, read as the kind declares it.
ConditionValue read_condition_value(const Reader& r, const toml::table& t, const ConditionKey& key, const std::string& path) {
  ConditionValue v;
  const std::string key_path = path + "." + key.name;
  if (key.type == ConditionKey::Type::time_function) {
    const toml::node& n = *t.get(key.name);
    v.where = r.at(n, key_path);
    v.function = r.time_function(n, key.dimension, key_path);
    return v;
  }
  if (key.type == ConditionKey::Type::choice) {
    const toml::node& n = *t.get(key.name);
    v.where = r.at(n, key_path);
    v.names.push_back(r.str(n, key_path));
    v.name_wheres.push_back(v.where);
    return v;
  }
  const auto* a = r.array(t, key.name);
  v.where = r.at(*a, key_path);
  for (const auto& e : *a) {
    v.names.push_back(r.str(e, key_path));
    v.name_wheres.push_back(r.at(e, key_path));
  }
  return v;
}

// [[boundary]] box = [x0, y0, x1, y1] or line = {from = [x, y], to = [x, y], tolerance = ...}.
std::optional<Region> read_region(const Reader& r, const toml::table& t, const std::string& path, std::string& where) {
  if (t.contains("box") && t.contains("line"))
    throw InputError(r.at(*t.get("line"), path + ".line") + ": give a box or a line, not both");
  Region g;
  if (const auto* a = r.array(t, "box")) {
    where = r.at(*a, path + ".box");
    if (a->size() != 4) throw InputError(where + ": expected [x0, y0, x1, y1] with units, e.g. [\"0 m\", \"0 m\", \"1 m\", \"20 m\"]");
    std::array<double, 4> b{};
    for (std::size_t i = 0; i < 4; ++i) b[i] = r.quantity(*a->get(i), Dimension::length, path + ".box");
    if (!(b[2] >= b[0] && b[3] >= b[1])) throw InputError(where + ": the box needs x0 <= x1 and y0 <= y1");
    g.box = b;
    return g;
  }
  const toml::node* n = t.get("line");
  if (!n) return std::nullopt;
  where = r.at(*n, path + ".line");
  const auto* lt = n->as_table();
  if (!lt) throw InputError(where + ": expected {from = [x, y], to = [x, y], tolerance = \"...\"} with units");
  r.check_keys(*lt, path + ".line", {"from", "to", "tolerance"});
  auto point = [&](const char* key) {
    const auto* p = r.array(*lt, key);
    if (!p || p->size() != 2) throw InputError(where + ": '" + key + "' must be [x, y] with units");
    return Vec2(r.quantity(*p->get(0), Dimension::length, path + ".line." + key),
                r.quantity(*p->get(1), Dimension::length, path + ".line." + key));
  };
  g.from = point("from");
  g.to = point("to");
  g.tolerance = r.positive(*lt, "tolerance", Dimension::length, path + ".line");
  return g;
}

// [[stages]] joints = { <joint name> = { <parameters that change> } }: from this stage on the joint
// has these values (the others as in [[joints]]); its contacts keep their state.
std::vector<StageInput::JointChange> read_joint_changes(const Reader& r, const toml::node& n, const std::string& path) {
  const auto* jt = n.as_table();
  if (!jt) throw InputError(r.at(n, path + ".joints") + ": expected a table { <joint name> = { <parameter> = <value>, ... } }");
  std::vector<StageInput::JointChange> changes;
  for (const auto& [k, v] : *jt) {
    StageInput::JointChange c;
    c.joint = std::string(k.str());
    const std::string key_path = path + ".joints." + c.joint;
    c.where = r.at(v, key_path);
    const auto* vt = v.as_table();
    if (!vt) throw InputError(c.where + ": expected a table of parameter values");
    c.params = raw_values(*vt, r.file, key_path);
    changes.push_back(std::move(c));
  }
  return changes;
}

// [[stages]] until = "equilibrium" | "duration" | "steps", with the keys of each.
void read_until(const Reader& r, const toml::table& t, const std::string& path, StageSpec& s) {
  const std::string until = r.str(t, "until", path, std::string("duration"));
  if (until == "equilibrium") {
    s.until = StageSpec::Until::equilibrium;
    s.ratio = r.positive(t, "ratio", Dimension::dimensionless, path, 1e-5);
    s.max_steps = r.integer(t, "max_steps", path, 1000000);
    const std::string at_max = r.str(t, "at_max_steps", path, std::string("fail"));
    if (at_max != "fail" && at_max != "continue")
      throw InputError(r.at(*t.get("at_max_steps"), path + ".at_max_steps") + ": must be \"fail\" (stop the run, exit code 3) "
                       "or \"continue\" (end the stage at max_steps with a warning), not '" + at_max + "'");
    s.continue_at_max_steps = at_max == "continue";
    if (t.contains("block_ratio")) s.block_ratio = r.positive(t, "block_ratio", Dimension::dimensionless, path, 0.0);
  } else if (until == "duration") {
    s.until = StageSpec::Until::duration;
    const toml::node* d = t.get("duration");
    if (d && d->as_string() && d->as_string()->get() == "auto") s.auto_duration = true;
    else s.duration = r.positive(t, "duration", Dimension::time, path);
  } else if (until == "steps") {
    s.until = StageSpec::Until::steps;
    s.steps = r.integer(t, "steps", path, 0);
    if (s.steps <= 0) throw InputError(r.at_table(t, path) + ": 'steps' must be a positive integer");
  } else {
    throw InputError(r.at(*t.get("until"), path + ".until") + ": unknown '" + until + "'; valid: equilibrium, duration, steps");
  }
}

// [direct_shear] test stages: one (shear_stage, normal_stress) or several (shear_stages, normal_stresses).
void read_test_stages(const Reader& r, const toml::table& t, const std::string& path, DirectShearInput& d) {
  const bool single = t.get("shear_stage") || t.get("normal_stress");
  const bool multi = t.get("shear_stages") || t.get("normal_stresses");
  if (single == multi)
    throw InputError(r.at_table(t, path) + ": give either shear_stage and normal_stress (one test stage) or the lists "
                     "shear_stages and normal_stresses (one entry per test stage), not both");
  if (single) {
    d.normal_stresses.push_back(r.positive(t, "normal_stress", Dimension::stress, path));
    d.shear_stages.push_back(r.str(t, "shear_stage", path));
    return;
  }
  const auto* sa = r.array(t, "shear_stages");
  const auto* na = r.array(t, "normal_stresses");
  if (!sa || !na || sa->size() != na->size() || sa->empty())
    throw InputError(r.at_table(t, path) + ": shear_stages and normal_stresses must be lists of the same, non-zero length");
  for (const auto& e : *sa) d.shear_stages.push_back(r.str(e, path + ".shear_stages"));
  for (const auto& e : *na) d.normal_stresses.push_back(r.quantity(e, Dimension::stress, path + ".normal_stresses"));
}

}  // namespace

std::string CaseReader::top_level(const toml::table& root) const {
  const Reader r{file_, base_dir_};
  // A file with tables of both dialects (a laboratory-test case's [specimen], [joint], [[stage]];
  // a DEM case's [[blocks]], [[joints]], [[stages]]) gets this rather than "unknown key", which
  // would suggest renaming its tables one by one.
  std::string lab, dem;
  for (const char* key : {"specimen", "element", "dem", "joint", "stage"})
    if (root.contains(key)) lab += (lab.empty() ? "[" : ", [") + std::string(key) + "]";
  for (const char* key : {"blocks", "rock_mass", "joints", "stages", "boundary", "histories"})
    if (root.contains(key)) dem += (dem.empty() ? "[" : ", [") + std::string(key) + "]";
  const bool lab_only = root.contains("specimen") || root.contains("element") || root.contains("dem");
  if (lab_only && dem.empty())  // not read as a laboratory-test case: [joint] or [[stage]] is missing
    throw InputError(file_ + ": has tables of a laboratory-test case file (" + lab + ") but no " +
                     (root.contains("joint") ? "[[stage]]" : root.contains("stage") ? "[joint]" : "[joint] and no [[stage]]") +
                     " table, which it needs (e.g. cases/direct_shear/test09_mohr_coulomb.toml; docs/case-files.md)");
  if (lab_only)
    throw InputError(file_ + ": has tables of a laboratory-test case file (" + lab + ") and of a DEM case file (" + dem +
                     "); a file is one or the other: a laboratory-test case has [specimen], [joint] and [[stage]] (e.g. "
                     "cases/direct_shear/test09_mohr_coulomb.toml, for `rockdem element`, `compare --case` and `run`), a DEM "
                     "case [[blocks]] or [rock_mass], [[joints]] and [[stages]] (e.g. cases/sliding_block/incline.toml, for "
                     "`rockdem run`); docs/case-files.md");
  r.check_keys(root, "case", {"title", "model", "time", "materials", "joints", "blocks", "rock_mass", "boundary",
                               "stages", "histories", "direct_shear", "output", "in_situ", "motions", "drift"});
  std::string title = r.str(root, "title", "case", std::string("untitled"));
  for (const char* key : {"model", "time", "rock_mass", "direct_shear", "output", "in_situ", "drift"})
    if (const toml::node* n = root.get(key); n && !n->is_table())
      throw InputError(r.at(*n, key) + ": expected a table, written [" + std::string(key) + "]");
  return title;
}

std::vector<const toml::table*> CaseReader::tables(const toml::table& root, const std::string& key) const {
  return Reader{file_, base_dir_}.tables(root, key);
}

ModelSettingsSpec CaseReader::model_settings(const toml::table& t) const {
  const Reader r{file_, base_dir_};
  r.check_keys(t, "model", {"rounding", "detection_tolerance", "gravity"});
  ModelSettingsSpec s;
  s.rounding = r.positive(t, "rounding", Dimension::length, "model", s.rounding);
  s.tolerance = r.quantity(t, "detection_tolerance", Dimension::length, "model", s.tolerance);
  if (s.tolerance < 0.0)
    throw InputError(r.at(*t.get("detection_tolerance"), "model.detection_tolerance") + ": must not be negative, got " +
                     format_quantity(s.tolerance, Dimension::length) + "; valid: 0 or more, e.g. \"1 mm\"");
  if (const auto* g = r.array(t, "gravity")) {
    if (g->size() != 2) throw InputError(r.at(*g, "model.gravity") + ": expected [gx, gy] with units");
    s.gravity = Vec2(r.quantity(*g->get(0), Dimension::acceleration, "model.gravity"),
                     r.quantity(*g->get(1), Dimension::acceleration, "model.gravity"));
  }
  return s;
}

TimeSpec CaseReader::time(const toml::table& t) const {
  const Reader r{file_, base_dir_};
  r.check_keys(t, "time", {"dt_safety", "fixed_dt", "mass_scaling_dt", "refresh_interval", "velocity_limit"});
  TimeSpec s;
  s.dt_safety = r.quantity(t, "dt_safety", Dimension::dimensionless, "time", 0.5);
  if (!(s.dt_safety > 0.0 && s.dt_safety <= 1.0)) throw InputError(r.at(*t.get("dt_safety"), "time.dt_safety") + ": must be in (0, 1]");
  s.fixed_dt = r.quantity(t, "fixed_dt", Dimension::time, "time", 0.0);
  s.mass_scaling_dt = r.quantity(t, "mass_scaling_dt", Dimension::time, "time", 0.0);
  s.refresh_interval = static_cast<int>(r.integer(t, "refresh_interval", "time", 10));
  if (s.refresh_interval < 1)
    throw InputError(r.at(*t.get("refresh_interval"), "time.refresh_interval") + ": must be a positive number of steps");
  s.velocity_limit = r.positive(t, "velocity_limit", Dimension::velocity, "time", 1e3);
  return s;
}

MaterialSpec CaseReader::material(const toml::table& t) const {
  const Reader r{file_, base_dir_};
  MaterialSpec s;
  s.name = r.str(t, "name", "materials");
  const std::string path = "materials." + s.name;
  s.model = r.str(t, "model", path);
  s.model_where = r.at(*t.get("model"), path + ".model");
  s.params = raw_values(t, r.file, path, {"name", "model"});
  s.where = r.at_table(t, path);
  return s;
}

namespace {

// The joint fitted in a calibrate/diagnose JSON, with the entry's own values set over it.
void apply_calibration(const std::string& file, const std::string& where, JointSpec& s) {
  const CalibratedJoint c = read_calibrated_joint(file, where);
  merge_calibration(c, s.law, s.law_where, s.params, s.effects);
  s.calibration = c.file;
  // The law's parameters now come from the file: a missing or bad one is looked for there.
  s.law_where += " (the joint of calibration file '" + c.file + "', with this entry's keys over it)";
}

// What a joint is (law, calibration, effects, parameters) from table `t`, read with `r` (the
// case file, or the file that replaces the entry: `rockdem run --joint NAME=FILE`).
void read_joint_law(const Reader& r, const toml::table& t, const std::string& path, JointSpec& s) {
  // calibration = "fit.json": the law, parameters and effects of `rockdem calibrate`/`diagnose`;
  // the table's own keys are set over them (calibration_file.hpp).
  const toml::node* calibration = t.get("calibration");
  s.law = calibration && !t.contains("law") ? std::string() : r.str(t, "law", path);
  s.effects = read_effects(r, t, path);
  s.params = raw_values(t, r.file, path, {"name", "law", "between", "effects", "joint_sets", "bridges", "calibration"});
  s.law_where = r.at(t.contains("law") ? *t.get("law") : *calibration, path + (t.contains("law") ? ".law" : ".calibration"));
  if (!calibration) return;
  const std::string where = r.at(*calibration, path + ".calibration");
  if (!calibration->is_string())
    throw InputError(where + ": give the path of a calibrate or diagnose JSON file, e.g. calibration = \"fits/test09_cy.json\"");
  apply_calibration(r.resolve(calibration->as_string()->get()), where, s);
}

}  // namespace

JointSpec CaseReader::joint(const toml::table& t, const std::string& replacement) const {
  const Reader r{file_, base_dir_};
  JointSpec s;
  s.name = r.str(t, "name", "joints");
  const std::string path = "joints." + s.name;
  const auto* between = r.array(t, "between");
  // Rock-mass edges: joint_sets and bridges (then 'between' defaults to any groups).
  if (const auto* sets = r.array(t, "joint_sets")) {
    s.joint_sets_where = r.at(*sets, path + ".joint_sets");
    for (const auto& e : *sets) s.joint_sets.push_back(r.str(e, path + ".joint_sets"));
    if (s.joint_sets.empty()) throw InputError(s.joint_sets_where + ": name at least one joint set or named joint");
  }
  s.bridges = r.boolean(t, "bridges", path, false);
  const bool by_edge = !s.joint_sets.empty() || s.bridges;
  if ((!between && !by_edge) || (between && between->size() != 2))
    throw InputError(r.at_table(t, path) + ": 'between' must name two block groups, e.g. between = [\"rock\", \"rock\"]"
                     " (or give joint_sets = [...] and/or bridges = true for rock-mass joints)");
  if (between) s.between = {r.str(*between->get(0), path + ".between"), r.str(*between->get(1), path + ".between")};
  if (replacement.empty()) {
    read_joint_law(r, t, path, s);
    return s;
  }
  // rockdem run --joint NAME=FILE: the entry keeps where it acts; what the joint is comes from
  // FILE, a calibrate/diagnose JSON or a TOML table with the keys of a [[joints]] entry.
  const std::string where = "--joint " + s.name + "=" + replacement;
  if (fs::path(replacement).extension() == ".json") {
    s.law_where = where;
    apply_calibration(replacement, where, s);
    return s;
  }
  const toml::table other = parse_toml_file(replacement, "joint file (" + where + ")");
  const Reader ro{replacement, fs::path(replacement).parent_path().string()};
  for (const char* key : {"name", "between", "joint_sets", "bridges"})
    if (other.contains(key))
      throw InputError(ro.at(*other.get(key), key) + ": a joint file gives what the joint is (law, parameters, effects, "
                       "calibration); where it acts ('" + std::string(key) + "') stays as in " + file_ + " [" + path + "]");
  read_joint_law(ro, other, path, s);
  return s;
}

BlockSpec CaseReader::block(const toml::table& t) const {
  const Reader r{file_, base_dir_};
  BlockSpec b;
  b.name = r.str(t, "name", "blocks");
  const std::string path = "blocks." + b.name;
  r.check_keys(t, path, {"name", "group", "type", "material", "density", "rectangle", "polygon", "zone_size", "zones", "mesh"});
  b.where = r.at_table(t, path);
  b.group = r.str(t, "group", path, b.name);
  const std::string type = r.str(t, "type", path, std::string("rigid"));
  if (type != "rigid" && type != "deformable")
    throw InputError(r.at(*t.get("type"), path + ".type") + ": must be 'rigid' or 'deformable', not '" + type + "'");
  b.rigid = type == "rigid";
  read_shape(r, t, path, b);
  if (b.rigid) {
    b.density = r.positive(t, "density", Dimension::density, path);
    return b;
  }
  b.material = r.str(t, "material", path);
  b.material_where = r.at(*t.get("material"), path + ".material");
  read_mesh(r, t, path, b);
  return b;
}

InSituSpec CaseReader::in_situ(const toml::table& t) const {
  const Reader r{file_, base_dir_};
  const std::string path = "in_situ";
  r.check_keys(t, path, {"surface", "density", "surcharge", "K", "sxy"});
  InSituSpec s;
  s.where = r.at_table(t, path);
  if (const toml::node* n = t.get("surface")) {
    s.surface = r.quantity(*n, Dimension::length, path + ".surface");
    s.surface_where = r.at(*n, path + ".surface");
  }
  if (const toml::node* n = t.get("density")) {
    s.density = r.quantity(*n, Dimension::density, path + ".density");
    s.density_where = r.at(*n, path + ".density");
    if (*s.density < 0.0) throw InputError(s.density_where + ": 'density' must not be negative");
  }
  s.surcharge = r.quantity(t, "surcharge", Dimension::stress, path, 0.0);
  // K has no default: a horizontal stress is a statement about the site, not a convention.
  s.k = r.quantity(t, "K", Dimension::dimensionless, path);
  if (!(s.k >= 0.0)) throw InputError(r.at(*t.get("K"), path + ".K") + ": K = sigma_H / sigma_v must be >= 0");
  s.sxy = r.quantity(t, "sxy", Dimension::stress, path, 0.0);
  return s;
}

BoundarySpec CaseReader::boundary(const toml::table& t) const {
  const Reader r{file_, base_dir_};
  const std::string path = "boundary";
  // Every kind's keys are valid in any [[boundary]]; a kind reads only its own.
  const ConditionKinds& kinds = ConditionKinds::instance();
  std::vector<std::string> keys{"type", "block", "face", "box", "line"};
  for (const auto& k : kinds.key_names()) keys.push_back(k);
  keys.push_back("stages");
  r.check_keys_in(t, path, keys);
  BoundarySpec b;
  b.where = r.at_table(t, path);
  b.type = r.str(t, "type", path);
  b.type_where = r.at(*t.get("type"), path + ".type");
  b.region = read_region(r, t, path, b.region_where);
  if (!b.region) {
    b.block = r.str(t, "block", path);
    b.block_where = r.at(r.need(t, "block", path), path + ".block");
  } else if (t.contains("block")) {
    throw InputError(r.at(*t.get("block"), path + ".block") + ": give either block (and face) or a region (box or line), not both");
  }
  b.face = r.str(t, "face", path, std::string("all"));
  b.face_given = t.contains("face");
  b.face_where = b.face_given ? r.at(*t.get("face"), path + ".face") : b.where;
  if (const ConditionKind* kind = kinds.find(b.type))
    for (const auto& key : kind->keys)
      if (t.contains(key.name)) b.values[key.name] = read_condition_value(r, t, key, path);
  if (const auto* st = r.array(t, "stages"))
    for (const auto& e : *st) b.stages.push_back(r.str(e, path + ".stages"));
  return b;
}

StageInput CaseReader::stage(const toml::table& t) const {
  const Reader r{file_, base_dir_};
  StageInput in;
  StageSpec& s = in.stage;
  s.name = r.str(t, "name", "stages");
  const std::string path = "stages." + s.name;
  r.check_keys(t, path, {"name", "damping", "local_damping", "damping_ratio", "damping_frequency", "rayleigh_terms", "until", "duration",
                         "steps", "ratio", "block_ratio", "max_steps", "at_max_steps", "joints", "excavate", "relax_steps",
                         "scale_off", "mass_scaling_dt", "mass_scaling", "motion", "motion_scale", "pga", "pgv"});
  if (const auto* jn = t.get("joints")) in.joint_changes = read_joint_changes(r, *jn, path);
  s.damping = read_damping(r, t, path);
  read_until(r, t, path, s);
  if (const auto* ex = r.array(t, "excavate"))
    for (const auto& e : *ex) {
      in.excavate.push_back(r.str(e, path + ".excavate"));
      in.excavate_wheres.push_back(r.at(e, path + ".excavate"));
    }
  read_stage_motions(r, t, path, in);
  s.relax_steps = r.integer(t, "relax_steps", path, 0);
  if (s.relax_steps < 0) throw InputError(r.at(*t.get("relax_steps"), path + ".relax_steps") + ": must be >= 0 steps");
  if (t.contains("relax_steps") && in.excavate.empty())
    throw InputError(r.at(*t.get("relax_steps"), path + ".relax_steps") + ": relax_steps releases the forces of "
                     "excavated blocks; the stage excavates none (add excavate = [...])");
  if (const toml::node* so = t.get("scale_off")) {
    s.scale_off = r.positive(t, "scale_off", Dimension::length, path);
    in.scale_off_where = r.at(*so, path + ".scale_off");
    if (s.until != StageSpec::Until::equilibrium)
      throw InputError(r.at(*so, path + ".scale_off") + ": scale_off takes out blocks that come loose while a stage seeks its "
                       "equilibrium; this stage runs until = \"" + r.str(t, "until", path, std::string("duration")) +
                       "\" (give until = \"equilibrium\", or leave scale_off out)");
  }
  if (t.contains("mass_scaling_dt") && t.contains("mass_scaling"))
    throw InputError(r.at(*t.get("mass_scaling"), path + ".mass_scaling") + ": give mass_scaling_dt (scaled) or "
                     "mass_scaling = false (real masses), not both");
  if (t.contains("mass_scaling_dt")) s.mass_scaling_dt = r.positive(t, "mass_scaling_dt", Dimension::time, path);
  if (t.contains("mass_scaling")) {
    if (r.boolean(t, "mass_scaling", path, false))
      throw InputError(r.at(*t.get("mass_scaling"), path + ".mass_scaling") + ": mass_scaling = true needs a time "
                       "step: write mass_scaling_dt = \"...\" instead");
    s.mass_scaling_dt = 0.0;
  }
  return in;
}

HistoryInput CaseReader::history(const toml::table& t) const {
  const Reader r{file_, base_dir_};
  HistoryInput h;
  h.name = r.str(t, "name", "histories");
  const std::string path = "histories." + h.name;
  r.check_keys(t, path, {"name", "quantity", "block", "component", "face", "scale", "unit", "description", "at", "to"});
  h.quantity = r.str(t, "quantity", path);
  h.quantity_where = r.at(*t.get("quantity"), path + ".quantity");
  const HistoryQuantity& q = HistoryQuantities::instance().get(h.quantity, h.quantity_where);
  h.unit = r.str(t, "unit", path, q.unit);
  h.description = r.str(t, "description", path, h.quantity);
  h.scale = r.quantity(t, "scale", Dimension::dimensionless, path, 1.0);
  if (const toml::node* n = t.get("component")) {
    h.component = r.str(*n, path + ".component");
    h.component_where = r.at(*n, path + ".component");
  }
  if (q.needs_point) {
    auto point = [&](const char* key, std::string& where) -> std::optional<Vec2> {
      const auto* a = r.array(t, key);
      if (!a) return std::nullopt;
      where = r.at(*a, path + "." + key);
      if (a->size() != 2) throw InputError(where + ": expected [x, y] with units, e.g. [\"2 m\", \"-1.5 m\"]");
      return Vec2(r.quantity(*a->get(0), Dimension::length, path + "." + key),
                  r.quantity(*a->get(1), Dimension::length, path + "." + key));
    };
    h.at = point("at", h.at_where);
    if (!h.at) throw InputError(r.at_table(t, path) + ": quantity '" + q.name + "' is measured by location: give at = [x, y]");
    h.to = point("to", h.to_where);
    if (h.to && !q.takes_segment)
      throw InputError(h.to_where + ": 'to' (a joint segment) is for contact quantities; '" + q.name + "' is measured at a point");
    return h;
  }
  if (!q.needs_block) return h;  // the other keys are not read then
  h.block = r.str(t, "block", path);
  h.block_where = r.at(r.need(t, "block", path), path + ".block");
  if (q.needs_face) {
    h.face = r.str(t, "face", path);
    h.face_where = r.at(*t.get("face"), path + ".face");
  }
  return h;
}

DirectShearInput CaseReader::direct_shear(const toml::table& t) const {
  const Reader r{file_, base_dir_};
  const std::string path = "direct_shear";
  r.check_keys(t, path, {"specimen", "joint_length", "loader", "other_loaders", "top", "bottom", "normal_stress",
                         "shear_stage", "normal_stresses", "shear_stages"});
  DirectShearInput d;
  d.where = r.at_table(t, path);
  d.specimen = r.str(t, "specimen", path);
  d.joint_length = r.positive(t, "joint_length", Dimension::length, path);
  const auto block = [&](const std::string& key, std::string& where) {
    std::string name = r.str(t, key, path);
    where = r.at(r.need(t, key, path), path + "." + key);
    return name;
  };
  d.loader = block("loader", d.loader_where);
  d.top = block("top", d.top_where);
  d.bottom = block("bottom", d.bottom_where);
  read_test_stages(r, t, path, d);
  if (const auto* ol = r.array(t, "other_loaders")) {
    for (const auto& e : *ol) {
      d.other_loaders.push_back(r.str(e, path + ".other_loaders"));
      d.other_loader_wheres.push_back(r.at(e, path + ".other_loaders"));
    }
  }
  return d;
}

DriftInput CaseReader::drift(const toml::table& t) const {
  const Reader r{file_, base_dir_};
  const std::string path = "drift";
  r.check_keys(t, path, {"opening", "reference_stage", "near", "initial_aperture", "residual_aperture",
                         "fall_displacement", "loosened"});
  DriftInput d;
  d.where = r.at_table(t, path);
  d.opening = r.str(t, "opening", path);
  d.opening_where = r.at(*t.get("opening"), path + ".opening");
  d.reference_stage = r.str(t, "reference_stage", path, std::string());
  if (const toml::node* n = t.get("reference_stage")) d.reference_where = r.at(*n, path + ".reference_stage");
  d.near = r.quantity(t, "near", Dimension::length, path, 5.5);
  d.initial_aperture = r.quantity(t, "initial_aperture", Dimension::length, path, 3e-4);
  d.residual_aperture = r.quantity(t, "residual_aperture", Dimension::length, path, 3e-5);
  d.fall_displacement = r.quantity(t, "fall_displacement", Dimension::length, path, 0.05);
  d.loosened = r.quantity(t, "loosened", Dimension::length, path, 5e-4);
  for (const auto& [key, value] : {std::pair<const char*, double>{"near", d.near}, {"initial_aperture", d.initial_aperture},
                                   {"fall_displacement", d.fall_displacement}, {"loosened", d.loosened}})
    if (!(value > 0.0))
      throw InputError((t.get(key) ? r.at(*t.get(key), path + "." + key) : d.where) + ": '" + key + "' must be a positive length");
  if (!(d.residual_aperture > 0.0 && d.residual_aperture <= d.initial_aperture))
    throw InputError((t.get("residual_aperture") ? r.at(*t.get("residual_aperture"), path + ".residual_aperture") : d.where) +
                     ": 'residual_aperture' must be positive and at most initial_aperture");
  return d;
}

void read_checkpoint_interval(const std::string& text, const std::string& where, OutputSpec& o) {
  const auto last = text.find_last_not_of(' ');
  const std::string t = text.substr(0, last == std::string::npos ? 0 : last + 1);
  for (const std::string unit : {" steps", " step"})
    if (t.size() > unit.size() && t.compare(t.size() - unit.size(), unit.size(), unit) == 0) {
      const std::string number = t.substr(0, t.size() - unit.size());
      std::size_t used = 0;
      long n = 0;
      try {
        n = std::stol(number, &used);
      } catch (const std::exception&) {
        used = 0;
      }
      if (used != number.size() || n <= 0)
        throw InputError(where + ": '" + text + "': the number of steps must be a positive whole number, e.g. \"20000 steps\"");
      o.checkpoint_steps = n;
      o.checkpoint_seconds = 0.0;
      return;
    }
  // Otherwise a wall-clock time ("30 min"), not simulated time.
  double seconds = 0.0;
  try {
    seconds = quantity_value(RawValue{text, where}, Dimension::time, where);
  } catch (const InputError& e) {
    throw InputError(std::string(e.what()) + "; give \"N steps\" or a wall-clock time such as \"30 min\"");
  }
  if (!(seconds > 0.0) || !std::isfinite(seconds))
    throw InputError(where + ": '" + text + "' must be a positive number of steps (\"20000 steps\") or a wall-clock time (\"30 min\")");
  o.checkpoint_seconds = seconds;
  o.checkpoint_steps = 0;
}

OutputSpec CaseReader::output(const toml::table& t) const {
  const Reader r{file_, base_dir_};
  r.check_keys(t, "output", {"history_interval", "vtk_interval", "progress_seconds", "checkpoint_every", "checkpoint_keep"});
  OutputSpec o;
  o.history_interval = r.integer(t, "history_interval", "output", 100);
  o.vtk_interval = r.integer(t, "vtk_interval", "output", 0);
  o.progress_seconds = r.quantity(t, "progress_seconds", Dimension::time, "output", 2.0);
  if (o.history_interval <= 0) throw InputError(r.at(*t.get("history_interval"), "output.history_interval") + ": must be positive");
  if (const toml::node* n = t.get("checkpoint_every")) {
    const auto text = n->value<std::string>();
    const std::string where = r.at(*n, "output.checkpoint_every");
    if (!text) throw InputError(where + ": give a string, \"N steps\" or a wall-clock time such as \"30 min\"");
    read_checkpoint_interval(*text, where, o);
  }
  o.checkpoint_keep = r.integer(t, "checkpoint_keep", "output", 3);
  if (o.checkpoint_keep < 0)
    throw InputError(r.at(*t.get("checkpoint_keep"), "output.checkpoint_keep") + ": must be 0 (keep all) or how many to keep");
  return o;
}

}  // namespace rockdem
