#include "framework/io/case.hpp"
#include "framework/io/measurement_csv.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>
#include <toml++/toml.h>

#include "framework/contact/detection.hpp"
#include "framework/core/error.hpp"
#include "framework/core/units.hpp"
#include "framework/geometry/mesh.hpp"
#include "framework/geometry/polygon.hpp"
#include "framework/io/toml_values.hpp"
#include "framework/mechanics/zones.hpp"
#include "framework/plugin_api/joint_law.hpp"
#include "framework/plugin_api/rock_material.hpp"

namespace rockdem {
namespace {

namespace fs = std::filesystem;

// Reading context: the file name for messages and the folder relative paths start from.
struct Reader {
  std::string file;
  std::string base_dir;

  std::string at(const toml::node& n, const std::string& key) const {
    return file + ":" + std::to_string(n.source().begin.line) + " key '" + key + "'";
  }
  std::string at_table(const toml::table& t, const std::string& path) const {
    return file + ":" + std::to_string(t.source().begin.line) + " [" + path + "]";
  }

  void check_keys(const toml::table& t, const std::string& path, std::initializer_list<std::string_view> allowed) const {
    for (auto&& [k, v] : t) {
      if (std::find(allowed.begin(), allowed.end(), k.str()) == allowed.end()) {
        std::string valid;
        for (auto a : allowed) valid += (valid.empty() ? "" : ", ") + std::string(a);
        throw InputError(at(v, path + "." + std::string(k.str())) + ": unknown key '" + std::string(k.str()) +
                         "' in [" + path + "]; valid keys: " + valid);
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
    if (kind == "file") {
      check_keys(*body, path, {"path", "time_unit", "value_unit", "holds", "time_column", "value_column"});
      const std::string holds = str(*body, "holds", path, std::string("velocity"));
      if (holds != "velocity" && holds != "displacement")
        throw InputError(at(*body, path + ".holds") + ": must be 'velocity' or 'displacement', not '" + holds + "'");
      const Dimension vd = holds == "displacement" ? Dimension::length : d;
      const double ts = parse_quantity("1 " + str(*body, "time_unit", path, std::string("s")), Dimension::time);
      const std::string vu = str(*body, "value_unit", path);
      double vs = 0.0;
      try {
        vs = parse_quantity("1 " + vu, vd);
      } catch (const InputError& e) {
        throw InputError(at(*body, path + ".value_unit") + ": " + e.what());
      }
      const std::string file_path = resolve(str(*body, "path", path));
      if (!fs::exists(file_path))
        throw InputError(at(*body, path + ".path") + ": data file '" + file_path + "' does not exist");
      // With column names the file is a CSV table with a header (e.g. a drive table time_s,
      // shear_disp_mm, or a measurement record); without, two bare columns.
      const bool named = body->contains("time_column") || body->contains("value_column");
      if (!named) return TimeFunction::from_file(file_path, ts, vs, holds == "displacement");
      const std::string tc = str(*body, "time_column", path), vc = str(*body, "value_column", path);
      const CsvTable tab = read_csv_table(file_path, {tc, vc}, "time-history table");
      std::vector<double> tt, vv;
      for (const auto& row : tab.rows) {
        tt.push_back(row[static_cast<std::size_t>(tab.column(tc))] * ts);
        vv.push_back(row[static_cast<std::size_t>(tab.column(vc))] * vs);
      }
      return TimeFunction::from_samples(std::move(tt), std::move(vv), holds == "displacement", file_path);
    }
    if (kind == "expression") {
      check_keys(*body, path, {"value", "unit"});
      const std::string unit = str(*body, "unit", path);
      double scale = 0.0;
      try {
        scale = parse_quantity("1 " + unit, d);
      } catch (const InputError& e) {
        throw InputError(at(*body, path + ".unit") + ": " + e.what());
      }
      try {
        const std::string expr = str(*body, "value", path);
        return TimeFunction::expression(scale == 1.0 ? expr : "(" + expr + ")*" + std::to_string(scale));
      } catch (const InputError& e) {
        throw InputError(at(*body, path + ".value") + ": " + e.what());
      }
    }
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
    const double f = r.positive(t, "damping_frequency", Dimension::frequency, path);
    if (xi < 0.0 || xi >= 1.0)
      throw InputError(r.at(*t.get("damping_ratio"), path + ".damping_ratio") + ": must be in [0, 1), got " + std::to_string(xi));
    return Damping::rayleigh(xi, f);
  }
  throw InputError(r.at(*t.get("damping"), path + ".damping") + ": unknown damping '" + kind +
                   "'; valid: local, rayleigh, none");
}

Case build(const toml::table& root, const Reader& r) {
  Case c;
  c.file = r.file;
  r.check_keys(root, "case", {"title", "model", "time", "materials", "joints", "blocks", "boundary", "stages",
                               "histories", "direct_shear", "output"});
  c.title = r.str(root, "title", "case", std::string("untitled"));
  Model& m = c.model;

  // [model]
  double rounding = 0.5e-3, tolerance = 1e-3;
  for (const char* key : {"model", "time", "direct_shear", "output"})
    if (const toml::node* n = root.get(key); n && !n->is_table())
      throw InputError(r.at(*n, key) + ": expected a table, written [" + std::string(key) + "]");
  if (const auto* t = root["model"].as_table()) {
    r.check_keys(*t, "model", {"rounding", "detection_tolerance", "gravity"});
    rounding = r.positive(*t, "rounding", Dimension::length, "model", rounding);
    tolerance = r.quantity(*t, "detection_tolerance", Dimension::length, "model", tolerance);
    if (const auto* g = r.array(*t, "gravity")) {
      if (g->size() != 2) throw InputError(r.at(*g, "model.gravity") + ": expected [gx, gy] with units");
      m.gravity = Vec2(r.quantity(*g->get(0), Dimension::acceleration, "model.gravity"),
                       r.quantity(*g->get(1), Dimension::acceleration, "model.gravity"));
    }
  }
  m.contacts.rounding = rounding;
  m.contacts.tolerance = tolerance;
  c.settings.detection.distance = rounding + tolerance;

  // [time]
  if (const auto* t = root["time"].as_table()) {
    r.check_keys(*t, "time", {"dt_safety", "fixed_dt", "mass_scaling_dt", "refresh_interval", "velocity_limit"});
    c.settings.dt_safety = r.quantity(*t, "dt_safety", Dimension::dimensionless, "time", 0.5);
    if (!(c.settings.dt_safety > 0.0 && c.settings.dt_safety <= 1.0))
      throw InputError(r.at(*t->get("dt_safety"), "time.dt_safety") + ": must be in (0, 1]");
    c.settings.fixed_dt = r.quantity(*t, "fixed_dt", Dimension::time, "time", 0.0);
    c.settings.mass_scaling_dt = r.quantity(*t, "mass_scaling_dt", Dimension::time, "time", 0.0);
    c.settings.refresh_interval = static_cast<int>(r.integer(*t, "refresh_interval", "time", 10));
    if (c.settings.refresh_interval < 1)
      throw InputError(r.at(*t->get("refresh_interval"), "time.refresh_interval") + ": must be a positive number of steps");
    c.settings.velocity_limit = r.positive(*t, "velocity_limit", Dimension::velocity, "time", 1e3);
  }

  // [[materials]]
  std::map<std::string, int> materials;
  for (const auto* t : r.tables(root, "materials")) {
    const std::string name = r.str(*t, "name", "materials");
    const std::string path = "materials." + name;
    const std::string model = r.str(*t, "model", path);
    const auto& entry = RockMaterialRegistry::instance().get(model, "rock material", r.at(*t->get("model"), path + ".model"));
    materials[name] = static_cast<int>(m.materials.size());
    m.materials.push_back(entry.make(raw_values(*t, r.file, path, {"name", "model"}), r.at_table(*t, path)));
  }

  // [[joints]]: joint models and the groups they act between.
  std::map<std::string, int> groups;
  auto group_index = [&](const std::string& g) {
    auto it = groups.find(g);
    if (it != groups.end()) return it->second;
    const int i = static_cast<int>(groups.size());
    groups[g] = i;
    return i;
  };
  struct PendingJoint {
    std::string a, b;
    int model;
  };
  std::vector<PendingJoint> pending;
  // What a stage needs to build the same joint with other parameter values.
  struct JointDefinition {
    std::string name, law;
    RawValues params;
    std::vector<EffectSpec> effects;
  };
  std::vector<JointDefinition> joint_defs;
  for (const auto* t : r.tables(root, "joints")) {
    const std::string name = r.str(*t, "name", "joints");
    const std::string path = "joints." + name;
    const std::string law = r.str(*t, "law", path);
    const auto* between = r.array(*t, "between");
    if (!between || between->size() != 2)
      throw InputError(r.at_table(*t, path) + ": 'between' must name two block groups, e.g. between = [\"rock\", \"rock\"]");
    std::vector<EffectSpec> effects;
    if (const auto* ea = r.array(*t, "effects")) {
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
    }
    const int index = static_cast<int>(m.contacts.models.size());
    RawValues params = raw_values(*t, r.file, path, {"name", "law", "between", "effects"});
    m.contacts.models.push_back(make_joint_model(law, params, effects, r.at(*t->get("law"), path + ".law")));
    m.contacts.model_names.push_back(name);
    joint_defs.push_back({name, law, std::move(params), effects});
    pending.push_back({r.str(*between->get(0), path + ".between"), r.str(*between->get(1), path + ".between"), index});
  }

  // [[blocks]]
  for (const auto* t : r.tables(root, "blocks")) {
    const std::string name = r.str(*t, "name", "blocks");
    const std::string path = "blocks." + name;
    r.check_keys(*t, path, {"name", "group", "type", "material", "density", "rectangle", "polygon", "zone_size",
                            "zones", "mesh"});
    if (std::find(c.block_names.begin(), c.block_names.end(), name) != c.block_names.end())
      throw InputError(r.at_table(*t, path) + ": a block named '" + name + "' already exists");
    const int group = group_index(r.str(*t, "group", path, name));
    const std::string type = r.str(*t, "type", path, std::string("rigid"));
    if (type != "rigid" && type != "deformable")
      throw InputError(r.at(*t->get("type"), path + ".type") + ": must be 'rigid' or 'deformable', not '" + type + "'");
    Polygon poly;
    double rx0 = 0, ry0 = 0, rw = 0, rh = 0;
    const bool is_rect = t->contains("rectangle");
    if (is_rect) {
      const auto* a = r.array(*t, "rectangle");
      if (a->size() != 4) throw InputError(r.at(*a, path + ".rectangle") + ": expected [x0, y0, width, height] with units");
      rx0 = r.quantity(*a->get(0), Dimension::length, path + ".rectangle");
      ry0 = r.quantity(*a->get(1), Dimension::length, path + ".rectangle");
      rw = r.quantity(*a->get(2), Dimension::length, path + ".rectangle");
      rh = r.quantity(*a->get(3), Dimension::length, path + ".rectangle");
      if (!(rw > 0 && rh > 0)) throw InputError(r.at(*a, path + ".rectangle") + ": width and height must be positive");
      poly = {{rx0, ry0}, {rx0 + rw, ry0}, {rx0 + rw, ry0 + rh}, {rx0, ry0 + rh}};
    } else if (const auto* a = r.array(*t, "polygon")) {
      poly = read_points(r, *a, path + ".polygon");
      if (!is_simple(poly)) throw InputError(r.at(*a, path + ".polygon") + ": the polygon intersects itself");
    } else {
      throw InputError(r.at_table(*t, path) + ": give the block's shape as rectangle = [x0, y0, width, height] or polygon = [[x, y], ...]");
    }
    if (type == "rigid") {
      const double rho = r.positive(*t, "density", Dimension::density, path);
      add_rigid_block(m, poly, rho, name, group);
    } else {
      const std::string mat = r.str(*t, "material", path);
      auto it = materials.find(mat);
      if (it == materials.end()) {
        std::string valid;
        for (const auto& [k, v] : materials) valid += (valid.empty() ? "" : ", ") + k;
        throw InputError(r.at(*t->get("material"), path + ".material") + ": unknown material '" + mat +
                         "'; defined materials: " + (valid.empty() ? "(none: add [[materials]])" : valid));
      }
      TriMesh mesh;
      if (const auto* z = r.array(*t, "zones")) {
        if (!is_rect) throw InputError(r.at(*z, path + ".zones") + ": zones = [nx, ny] is for rectangles; use zone_size for polygons");
        const auto nx = z->size() == 2 ? z->get(0)->value<int64_t>() : std::nullopt;
        const auto ny = z->size() == 2 ? z->get(1)->value<int64_t>() : std::nullopt;
        if (!nx || !ny || *nx < 1 || *ny < 1) throw InputError(r.at(*z, path + ".zones") + ": expected [nx, ny], positive integers");
        mesh = mesh_rectangle(rx0, ry0, rw, rh, static_cast<int>(*nx), static_cast<int>(*ny));
      } else {
        const double h = r.positive(*t, "zone_size", Dimension::length, path);
        const std::string mesh_kind = r.str(*t, "mesh", path, std::string(is_rect ? "structured" : "unstructured"));
        if (mesh_kind != "structured" && mesh_kind != "unstructured")
          throw InputError(r.at(*t->get("mesh"), path + ".mesh") + ": unknown mesh '" + mesh_kind + "'; valid: structured (rectangles), unstructured");
        if (mesh_kind == "structured" && !is_rect)
          throw InputError(r.at(*t->get("mesh"), path + ".mesh") + ": a structured mesh needs rectangle = [...]; use mesh = \"unstructured\" for polygons");
        if (mesh_kind == "structured") {
          mesh = mesh_rectangle(rx0, ry0, rw, rh, std::max(1, static_cast<int>(std::lround(rw / h))),
                                std::max(1, static_cast<int>(std::lround(rh / h))));
        } else {
          mesh = mesh_polygon(poly, h);
        }
      }
      add_deformable_block(m, mesh, it->second, name, group);
    }
    c.block_names.push_back(name);
  }
  if (m.blocks.empty()) throw InputError(r.file + ": the case defines no blocks; add [[blocks]]");

  // Overlapping blocks at the start are an input error (touching along an edge is fine). Only
  // pairs whose boxes meet are tested (the contact broad phase), so large models stay cheap.
  for (const auto& [i, j] : broad_phase(m, 0.0)) {
    Polygon a, b;
    for (int g : m.blocks[i].boundary) a.push_back(m.gp[g].x);
    for (int g : m.blocks[j].boundary) b.push_back(m.gp[g].x);
    if (polygons_overlap(a, b, 1e-9 * std::sqrt(std::abs(signed_area(a)))))
      throw InputError(r.file + ": blocks '" + m.blocks[i].name + "' and '" + m.blocks[j].name +
                       "' overlap at the start (intersection area " + std::to_string(intersection_area(a, b)) +
                       " m^2); blocks may touch but not overlap");
  }

  m.contacts.group_names.resize(groups.size());
  for (const auto& [g, i] : groups) m.contacts.group_names[static_cast<std::size_t>(i)] = g;
  for (const auto& pj : pending) {
    auto ga = groups.find(pj.a), gb = groups.find(pj.b);
    const bool any_a = pj.a == "*", any_b = pj.b == "*";
    if ((!any_a && ga == groups.end()) || (!any_b && gb == groups.end())) {
      std::string valid;
      for (const auto& [k, v] : groups) valid += (valid.empty() ? "" : ", ") + k;
      throw InputError(r.file + ": joint '" + m.contacts.model_names[static_cast<std::size_t>(pj.model)] +
                       "' names a block group '" + (ga == groups.end() ? pj.a : pj.b) +
                       "' that no block has; groups: " + valid + " (or \"*\" for any)");
    }
    m.contacts.assignments.push_back({any_a ? -1 : ga->second, any_b ? -1 : gb->second, pj.model});
  }

  // [[boundary]]
  for (const auto* t : r.tables(root, "boundary")) {
    const std::string path = "boundary";
    r.check_keys(*t, path, {"type", "block", "face", "components", "vx", "vy", "spin", "normal", "shear", "stages"});
    const std::string type = r.str(*t, "type", path);
    const int block = c.block_index(r.str(*t, "block", path), r.at(r.need(*t, "block", path), path + ".block"));
    const std::string face = r.str(*t, "face", path, std::string("all"));
    const auto sel = select_face(m, block, face_direction(face, t->get("face") ? r.at(*t->get("face"), path + ".face") : r.at_table(*t, path)));
    if (sel.points.empty())
      throw InputError(r.at_table(*t, path) + ": face '" + face + "' of block '" + m.blocks[block].name + "' has no gridpoints");
    const bool rigid = m.blocks[block].rigid;
    if (rigid && t->contains("face") && (type == "fixed" || type == "velocity"))
      throw InputError(r.at(*t->get("face"), path + ".face") + ": block '" + m.blocks[block].name +
                       "' is rigid; a " + type + " condition acts on the whole rigid block, so leave out 'face'");
    std::unique_ptr<BoundaryCondition> bc;
    if (type == "fixed") {
      bool fx = true, fy = true;
      if (const auto* comps = r.array(*t, "components")) {
        fx = fy = false;
        for (const auto& e : *comps) {
          const std::string s = r.str(e, path + ".components");
          if (s == "x") fx = true;
          else if (s == "y") fy = true;
          else throw InputError(r.at(e, path + ".components") + ": unknown component '" + s + "'; valid: x, y");
        }
      }
      if (rigid && !(fx && fy)) {
        // Holding one component of a rigid block: a zero velocity on that component only.
        bc = std::make_unique<VelocityCondition>(sel, true, fx ? std::optional(TimeFunction::constant(0.0)) : std::nullopt,
                                                 fy ? std::optional(TimeFunction::constant(0.0)) : std::nullopt, std::nullopt);
      } else {
        bc = std::make_unique<FixedCondition>(sel, fx, fy, rigid);
      }
    } else if (type == "velocity") {
      std::optional<TimeFunction> vx, vy, spin;
      if (const auto* n = t->get("vx")) vx = r.time_function(*n, Dimension::velocity, path + ".vx");
      if (const auto* n = t->get("vy")) vy = r.time_function(*n, Dimension::velocity, path + ".vy");
      if (const auto* n = t->get("spin")) spin = r.time_function(*n, Dimension::angular_velocity, path + ".spin");
      if (!vx && !vy && !spin) throw InputError(r.at_table(*t, path) + ": a velocity condition needs vx, vy or spin");
      if (spin && !rigid) throw InputError(r.at(*t->get("spin"), path + ".spin") + ": spin applies to rigid blocks only");
      bc = std::make_unique<VelocityCondition>(sel, rigid, vx, vy, spin);
    } else if (type == "traction") {
      TimeFunction sn = TimeFunction::constant(0.0), ss = TimeFunction::constant(0.0);
      if (const auto* n = t->get("normal")) sn = r.time_function(*n, Dimension::stress, path + ".normal");
      if (const auto* n = t->get("shear")) ss = r.time_function(*n, Dimension::stress, path + ".shear");
      bc = std::make_unique<TractionCondition>(sel, sn, ss);
    } else if (type == "quiet") {
      if (rigid) throw InputError(r.at_table(*t, path) + ": quiet boundaries act on deformable blocks");
      const auto& mat = *m.materials[static_cast<std::size_t>(m.zones[static_cast<std::size_t>(m.blocks[block].first_zone)].material)];
      const double rho = mat.density(), k = mat.bulk_modulus(), g = mat.shear_modulus();
      bc = std::make_unique<QuietCondition>(sel, rho, std::sqrt((k + 4.0 * g / 3.0) / rho), std::sqrt(g / rho));
    } else {
      throw InputError(r.at(*t->get("type"), path + ".type") + ": unknown boundary type '" + type +
                       "'; valid: fixed, velocity, traction, quiet");
    }
    if (const auto* st = r.array(*t, "stages"))
      for (const auto& e : *st) bc->stages.push_back(r.str(e, path + ".stages"));
    c.conditions.push_back(std::move(bc));
  }

  // [[stages]]
  for (const auto* t : r.tables(root, "stages")) {
    StageSpec s;
    s.name = r.str(*t, "name", "stages");
    const std::string path = "stages." + s.name;
    r.check_keys(*t, path, {"name", "damping", "local_damping", "damping_ratio", "damping_frequency", "until",
                            "duration", "steps", "ratio", "max_steps", "joints"});
    // joints = { <joint name> = { <parameters that change> } }: from this stage on the joint has
    // these values (the others as in [[joints]]); its contacts keep their state.
    if (const auto* jn = t->get("joints")) {
      const auto* jt = jn->as_table();
      if (!jt) throw InputError(r.at(*jn, path + ".joints") + ": expected a table { <joint name> = { <parameter> = <value>, ... } }");
      for (const auto& [k, v] : *jt) {
        const std::string jname(k.str());
        auto def = std::find_if(joint_defs.begin(), joint_defs.end(), [&](const JointDefinition& d) { return d.name == jname; });
        if (def == joint_defs.end()) {
          std::string valid;
          for (const auto& d : joint_defs) valid += (valid.empty() ? "" : ", ") + d.name;
          throw InputError(r.at(v, path + ".joints." + jname) + ": no joint named '" + jname + "'; joints: " + valid);
        }
        const auto* vt = v.as_table();
        if (!vt) throw InputError(r.at(v, path + ".joints." + jname) + ": expected a table of parameter values");
        RawValues merged = def->params;
        for (auto& [pk, pv] : raw_values(*vt, r.file, path + ".joints." + jname)) merged[pk] = pv;
        s.joint_models.emplace_back(static_cast<int>(def - joint_defs.begin()),
                                    make_joint_model(def->law, merged, def->effects, r.at(v, path + ".joints." + jname)));
      }
    }
    s.damping = read_damping(r, *t, path);
    const std::string until = r.str(*t, "until", path, std::string("duration"));
    if (until == "equilibrium") {
      s.until = StageSpec::Until::equilibrium;
      s.ratio = r.positive(*t, "ratio", Dimension::dimensionless, path, 1e-5);
      s.max_steps = r.integer(*t, "max_steps", path, 1000000);
    } else if (until == "duration") {
      s.until = StageSpec::Until::duration;
      const toml::node* d = t->get("duration");
      if (d && d->as_string() && d->as_string()->get() == "auto") s.auto_duration = true;
      else s.duration = r.positive(*t, "duration", Dimension::time, path);
    } else if (until == "steps") {
      s.until = StageSpec::Until::steps;
      s.steps = r.integer(*t, "steps", path, 0);
      if (s.steps <= 0) throw InputError(r.at_table(*t, path) + ": 'steps' must be a positive integer");
    } else {
      throw InputError(r.at(*t->get("until"), path + ".until") + ": unknown '" + until + "'; valid: equilibrium, duration, steps");
    }
    c.stages.push_back(s);
  }
  if (c.stages.empty()) throw InputError(r.file + ": the case defines no stages; add [[stages]]");
  std::set<std::string> stage_names;
  for (const auto& s : c.stages) stage_names.insert(s.name);
  for (const auto& bc : c.conditions)
    for (const auto& s : bc->stages)
      if (!stage_names.count(s)) {
        std::string valid;
        for (const auto& n : stage_names) valid += (valid.empty() ? "" : ", ") + n;
        throw InputError(r.file + ": a boundary condition names stage '" + s + "' that does not exist; stages: " + valid);
      }

  // [[histories]]
  for (const auto* t : r.tables(root, "histories")) {
    HistorySpec h;
    h.name = r.str(*t, "name", "histories");
    const std::string path = "histories." + h.name;
    r.check_keys(*t, path, {"name", "quantity", "block", "component", "face", "scale", "unit", "description"});
    const std::string q = r.str(*t, "quantity", path);
    static const std::map<std::string, std::pair<HistorySpec::Quantity, std::string>> kinds{
        {"contact_force", {HistorySpec::Quantity::contact_force, "N/m"}},
        {"block_displacement", {HistorySpec::Quantity::block_displacement, "m"}},
        {"block_velocity", {HistorySpec::Quantity::block_velocity, "m/s"}},
        {"face_displacement", {HistorySpec::Quantity::face_displacement, "m"}},
        {"unbalanced_ratio", {HistorySpec::Quantity::unbalanced_ratio, ""}},
        {"kinetic_energy", {HistorySpec::Quantity::kinetic_energy, "J/m"}},
        {"time_step", {HistorySpec::Quantity::time_step, "s"}}};
    auto it = kinds.find(q);
    if (it == kinds.end()) {
      std::string valid;
      for (const auto& [k, v] : kinds) valid += (valid.empty() ? "" : ", ") + k;
      throw InputError(r.at(*t->get("quantity"), path + ".quantity") + ": unknown quantity '" + q + "'; valid: " + valid);
    }
    h.quantity = it->second.first;
    h.unit = r.str(*t, "unit", path, it->second.second);
    h.description = r.str(*t, "description", path, q);
    h.scale = r.quantity(*t, "scale", Dimension::dimensionless, path, 1.0);
    const bool needs_block = h.quantity == HistorySpec::Quantity::contact_force ||
                             h.quantity == HistorySpec::Quantity::block_displacement ||
                             h.quantity == HistorySpec::Quantity::block_velocity ||
                             h.quantity == HistorySpec::Quantity::face_displacement;
    if (needs_block) {
      h.block = c.block_index(r.str(*t, "block", path), r.at(r.need(*t, "block", path), path + ".block"));
      const std::string comp = r.str(*t, "component", path, std::string("x"));
      if (comp == "x") h.component = 0;
      else if (comp == "y") h.component = 1;
      else if (comp == "rotation" && h.quantity == HistorySpec::Quantity::block_displacement) h.component = 2;
      else throw InputError(r.at(*t->get("component"), path + ".component") + ": unknown component '" + comp + "'; valid: x, y" +
                            (h.quantity == HistorySpec::Quantity::block_displacement ? ", rotation" : ""));
      if ((h.quantity == HistorySpec::Quantity::block_displacement || h.quantity == HistorySpec::Quantity::block_velocity) &&
          !m.blocks[h.block].rigid)
        throw InputError(r.at(*t->get("quantity"), path + ".quantity") + ": '" + q + "' is for rigid blocks; block '" +
                         m.blocks[h.block].name + "' is deformable: use face_displacement");
      if (h.quantity == HistorySpec::Quantity::face_displacement) {
        const std::string face = r.str(*t, "face", path);
        h.points = select_face(m, h.block, face_direction(face, r.at(*t->get("face"), path + ".face"))).points;
      }
    }
    c.histories.push_back(h);
  }

  // [direct_shear]
  if (const auto* t = root["direct_shear"].as_table()) {
    const std::string path = "direct_shear";
    r.check_keys(*t, path, {"specimen", "joint_length", "loader", "other_loaders", "top", "bottom", "normal_stress", "shear_stage",
                            "normal_stresses", "shear_stages"});
    auto& d = c.direct_shear;
    d.enabled = true;
    d.specimen = r.str(*t, "specimen", path);
    d.joint_length = r.positive(*t, "joint_length", Dimension::length, path);
    d.loader = c.block_index(r.str(*t, "loader", path), r.at(r.need(*t, "loader", path), path + ".loader"));
    d.top = c.block_index(r.str(*t, "top", path), r.at(r.need(*t, "top", path), path + ".top"));
    d.bottom = c.block_index(r.str(*t, "bottom", path), r.at(r.need(*t, "bottom", path), path + ".bottom"));
    // One test stage (shear_stage, normal_stress) or several (shear_stages, normal_stresses).
    const bool single = t->get("shear_stage") || t->get("normal_stress");
    const bool multi = t->get("shear_stages") || t->get("normal_stresses");
    if (single == multi)
      throw InputError(r.at_table(*t, path) + ": give either shear_stage and normal_stress (one test stage) or the lists "
                       "shear_stages and normal_stresses (one entry per test stage), not both");
    if (single) {
      d.normal_stresses.push_back(r.positive(*t, "normal_stress", Dimension::stress, path));
      d.shear_stages.push_back(r.str(*t, "shear_stage", path));
    } else {
      const auto* sa = r.array(*t, "shear_stages");
      const auto* na = r.array(*t, "normal_stresses");
      if (!sa || !na || sa->size() != na->size() || sa->empty())
        throw InputError(r.at_table(*t, path) + ": shear_stages and normal_stresses must be lists of the same, non-zero length");
      for (const auto& e : *sa) d.shear_stages.push_back(r.str(e, path + ".shear_stages"));
      for (const auto& e : *na) d.normal_stresses.push_back(r.quantity(e, Dimension::stress, path + ".normal_stresses"));
    }
    for (const auto& s : d.shear_stages)
      if (!stage_names.count(s)) {
        std::string valid;
        for (const auto& n : stage_names) valid += (valid.empty() ? "" : ", ") + n;
        throw InputError(r.at_table(*t, path) + ": no stage named '" + s + "'; stages: " + valid);
      }
    d.top_face = select_face(m, d.top, {0, -1}).points;
    d.bottom_face = select_face(m, d.bottom, {0, 1}).points;
    if (!m.blocks[d.loader].rigid) throw InputError(r.at(*t->get("loader"), path + ".loader") + ": the loading block must be rigid");
    if (const auto* ol = r.array(*t, "other_loaders")) {
      for (const auto& e : *ol) {
        const int b = c.block_index(r.str(e, path + ".other_loaders"), r.at(e, path + ".other_loaders"));
        if (!m.blocks[b].rigid) throw InputError(r.at(e, path + ".other_loaders") + ": a loading block must be rigid");
        d.other_loaders.push_back(b);
      }
    }
  }

  // [output]
  if (const auto* t = root["output"].as_table()) {
    r.check_keys(*t, "output", {"history_interval", "vtk_interval", "progress_seconds"});
    c.output.history_interval = r.integer(*t, "history_interval", "output", 100);
    c.output.vtk_interval = r.integer(*t, "vtk_interval", "output", 0);
    c.output.progress_seconds = r.quantity(*t, "progress_seconds", Dimension::time, "output", 2.0);
    if (c.output.history_interval <= 0) throw InputError(r.at(*t->get("history_interval"), "output.history_interval") + ": must be positive");
  }
  return c;
}

Case parse(const std::string& text, const std::string& name, const std::string& base_dir, bool from_file) {
  toml::table root;
  try {
    root = from_file ? toml::parse_file(name) : toml::parse(text, name);
  } catch (const toml::parse_error& e) {
    throw InputError(name + ":" + std::to_string(e.source().begin.line) + ":" + std::to_string(e.source().begin.column) +
                     ": TOML syntax error: " + std::string(e.description()));
  }
  return build(root, Reader{name, base_dir});
}

}  // namespace

int Case::block_index(const std::string& name, const std::string& where) const {
  for (std::size_t i = 0; i < block_names.size(); ++i)
    if (block_names[i] == name) return static_cast<int>(i);
  std::string valid;
  for (const auto& n : block_names) valid += (valid.empty() ? "" : ", ") + n;
  throw InputError(where + ": unknown block '" + name + "'; blocks: " + valid);
}

Case load_case(const std::string& path) {
  if (!fs::exists(path)) throw InputError(path + ": case file does not exist");
  return parse("", path, fs::path(path).parent_path().string(), true);
}

Case load_case_text(const std::string& text, const std::string& name, const std::string& base_dir) {
  return parse(text, name, base_dir, false);
}

Case load_case_table(const toml::table& root, const std::string& name, const std::string& base_dir) {
  return build(root, Reader{name, base_dir});
}

}  // namespace rockdem
