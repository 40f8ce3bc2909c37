#include "framework/io/rock_mass_reader.hpp"

#include <algorithm>
#include <cmath>
#include <set>

#include "framework/core/error.hpp"
#include "framework/core/names.hpp"
#include "framework/core/units.hpp"
#include "framework/io/toml_table.hpp"
#include "framework/io/toml_values.hpp"

namespace rockdem {
namespace {

using Table = TomlTable;

JointSetInput joint_set(const Table& t, std::set<std::string>& names) {
  t.only({"name", "dip", "spacing", "trace", "gap", "persistence", "origin", "dip_sd", "spacing_sd", "trace_sd", "gap_sd",
          "region"});
  JointSetInput s;
  s.name = t.name(names);
  s.where = t.here() + " '" + s.name + "'";
  s.dip = t.value(t.required("dip"), "dip", Dimension::angle);
  s.spacing = t.at_least("spacing", Dimension::length, std::nullopt);
  s.trace = t.at_least("trace", Dimension::length, std::numeric_limits<double>::infinity());
  const auto gap = t.maybe("gap", Dimension::length);
  const auto persistence = t.maybe("persistence", Dimension::dimensionless);
  if (gap && persistence) throw InputError(s.where + ": give either gap or persistence, not both");
  if ((gap || persistence) && !std::isfinite(s.trace))
    throw InputError(s.where + ": a gap or persistence needs a finite trace length (trace = \"...\")");
  if (gap) s.gap = t.at_least("gap", Dimension::length, std::nullopt, true);
  if (persistence) {
    if (!(*persistence > 0.0 && *persistence <= 1.0))
      throw InputError(t.key_at(*t.t.get("persistence"), "persistence") + ": must be in (0, 1] (trace / (trace + gap))");
    s.gap = s.trace * (1.0 - *persistence) / *persistence;
  }
  s.origin = t.t.contains("origin") ? t.point("origin") : Vec2::Zero();
  s.dip_sd = t.at_least("dip_sd", Dimension::angle, 0.0, true);
  s.spacing_sd = t.at_least("spacing_sd", Dimension::length, 0.0, true);
  s.trace_sd = t.at_least("trace_sd", Dimension::length, 0.0, true);
  s.gap_sd = t.at_least("gap_sd", Dimension::length, 0.0, true);
  if (const toml::node* r = t.t.get("region")) {
    const auto* rt = r->as_table();
    if (!rt) throw InputError(t.key_at(*r, "region") + ": expected { rectangle = [...] } or { polygon = [...] }");
    const Table region{*rt, t.file, t.path + ".region"};
    region.only({"rectangle", "polygon"});
    s.region = region.shape("the set's region");
  }
  return s;
}

OpeningInput opening(const Table& t, std::set<std::string>& names) {
  OpeningInput o;
  o.name = t.name(names);
  o.where = t.here() + " '" + o.name + "'";
  const std::string shape = t.text("shape", std::string("circle"));
  if (shape == "circle") {
    t.only({"name", "shape", "centre", "radius", "segments"});
    o.shape = OpeningInput::Shape::circle;
    o.centre = t.point("centre");
    o.radius = t.at_least("radius", Dimension::length, std::nullopt);
  } else if (shape == "horseshoe") {
    t.only({"name", "shape", "centre", "width", "wall_height", "arch_rise", "segments"});
    o.shape = OpeningInput::Shape::horseshoe;
    o.centre = t.point("centre");
    o.width = t.at_least("width", Dimension::length, std::nullopt);
    o.wall_height = t.at_least("wall_height", Dimension::length, std::nullopt);
    o.arch_rise = t.at_least("arch_rise", Dimension::length, 0.5 * o.width);
    if (o.arch_rise > 0.5 * o.width)
      throw InputError(t.key_at(*t.t.get("arch_rise"), "arch_rise") + ": must not exceed half the width");
  } else if (shape == "polygon") {
    t.only({"name", "shape", "polygon"});
    o.shape = OpeningInput::Shape::polygon;
    o.polygon = t.shape("the opening");
  } else {
    throw InputError(t.key_at(*t.t.get("shape"), "shape") + ": unknown shape '" + shape + "'; valid: circle, horseshoe, polygon");
  }
  if (const toml::node* n = t.t.get("segments")) {
    const auto k = n->value<std::int64_t>();
    if (!k || *k < 3 || *k > 100000)
      throw InputError(t.key_at(*n, "segments") + ": expected an integer from 3 to 100000 (sides of the circle or arch)");
    o.segments = static_cast<int>(*k);
  }
  return o;
}

RegionInput region(const Table& t, std::set<std::string>& names) {
  t.only({"name", "rectangle", "polygon", "jointed", "zone_size"});
  RegionInput r;
  r.name = t.name(names);
  r.where = t.here() + " '" + r.name + "'";
  r.polygon = t.shape("the region");
  r.jointed = t.flag("jointed", true);
  r.zone_size = t.at_least("zone_size", Dimension::length, 0.0, true);
  return r;
}

NamedJointInput named_joint(const Table& t, std::set<std::string>& names) {
  t.only({"name", "from", "to"});
  NamedJointInput j;
  j.name = t.name(names);
  j.where = t.here() + " '" + j.name + "'";
  j.a = t.point("from");
  j.b = t.point("to");
  return j;
}

}  // namespace

RockMassSpec read_rock_mass(const toml::table& root, const std::string& file) {
  const Table t{root, file, "rock_mass"};
  t.only({"rectangle", "polygon", "type", "density", "material", "zone_size", "seed", "group", "prefix",
          "sliver_area_fraction", "sliver_roundness", "joint_sets", "joints", "openings", "regions"});
  RockMassSpec s;
  s.where = t.here();
  RockMassInput& g = s.geometry;
  g.domain = t.shape("the domain");
  g.domain_where = t.here() + " (domain)";
  const std::string type = t.text("type", std::string("rigid"));
  if (type != "rigid" && type != "deformable")
    throw InputError(t.key_at(*t.t.get("type"), "type") + ": must be 'rigid' or 'deformable', not '" + type + "'");
  s.rigid = type == "rigid";
  if (s.rigid) {
    s.density = t.at_least("density", Dimension::density, std::nullopt);
  } else {
    s.material = t.text("material");
    s.material_where = t.key_at(t.required("material"), "material");
    s.zone_size = t.at_least("zone_size", Dimension::length, std::nullopt);
  }
  if (const toml::node* n = t.t.get("seed")) {
    const auto v = n->value<std::int64_t>();
    if (!v || *v < 0) throw InputError(t.key_at(*n, "seed") + ": expected a non-negative integer");
    g.seed = static_cast<std::uint64_t>(*v);
  }
  s.group = t.text("group", s.group);
  s.prefix = t.text("prefix", s.prefix);
  g.sliver.area_fraction = t.at_least("sliver_area_fraction", Dimension::dimensionless, g.sliver.area_fraction, true);
  g.sliver.roundness = t.at_least("sliver_roundness", Dimension::dimensionless, g.sliver.roundness, true);
  if (g.sliver.roundness >= 1.0)
    throw InputError(t.key_at(*t.t.get("sliver_roundness"), "sliver_roundness") + ": must be below 1 (a circle's)");
  std::set<std::string> names;
  for (const auto& e : t.entries("joint_sets")) g.joint_sets.push_back(joint_set(e, names));
  for (const auto& e : t.entries("joints")) g.joints.push_back(named_joint(e, names));
  for (const auto& e : t.entries("openings")) g.openings.push_back(opening(e, names));
  for (const auto& e : t.entries("regions")) g.regions.push_back(region(e, names));
  if (g.joint_sets.empty() && g.joints.empty() && g.openings.empty() && g.regions.empty())
    throw InputError(t.here() + ": the rock mass has no joint sets, joints, openings or regions, so it would be one block; "
                     "add [[rock_mass.joint_sets]] (or write the block as [[blocks]])");
  return s;
}

}  // namespace rockdem
