#include <string>

#include "framework/io/rock_mass_spec.hpp"

namespace rockdem {
namespace {

std::optional<EdgeLabel> edge_label(const RockMassInput& g, const EdgeTag& t) {
  const auto source_name = [&](int s) {
    const auto i = static_cast<std::size_t>(s);
    return i < g.joint_sets.size() ? g.joint_sets[i].name : g.joints[i - g.joint_sets.size()].name;
  };
  switch (t.kind) {
    case EdgeKind::joint: return EdgeLabel{source_name(t.source), false};
    case EdgeKind::bridge: return EdgeLabel{source_name(t.source), true};
    case EdgeKind::cut: return EdgeLabel{"", true};
    case EdgeKind::domain: break;
  }
  return std::nullopt;
}

}  // namespace

std::vector<BlockSpec> rock_mass_blocks(const RockMassSpec& spec, RockMass* out) {
  RockMass rm = generate_rock_mass(spec.geometry);
  const auto& g = spec.geometry;
  std::vector<int> per_opening(g.openings.size(), 0);
  for (const auto& b : rm.blocks)
    if (b.opening >= 0) ++per_opening[static_cast<std::size_t>(b.opening)];
  std::vector<int> opening_count(g.openings.size(), 0);
  std::vector<BlockSpec> blocks;
  int rock = 0;
  for (const auto& b : rm.blocks) {
    BlockSpec s;
    const RegionInput* region = b.region >= 0 ? &g.regions[static_cast<std::size_t>(b.region)] : nullptr;
    if (b.opening >= 0) {
      const auto o = static_cast<std::size_t>(b.opening);
      s.name = g.openings[o].name;
      if (per_opening[o] > 1) s.name.append(".").append(std::to_string(opening_count[o]++));
      s.group = g.openings[o].name;
    } else {
      // Appended piece by piece: GCC 12 warns falsely (-Wrestrict) on prefix + "." + number.
      s.name = spec.prefix;
      s.name.append(".").append(std::to_string(rock++));
      s.group = region ? region->name : spec.group;
    }
    s.rigid = spec.rigid;
    s.polygon = b.polygon;
    s.density = spec.density;
    s.material = spec.material;
    s.zone_size = region && region->zone_size > 0.0 ? region->zone_size : spec.zone_size;
    s.mesh = BlockSpec::Mesh::unstructured;
    for (const auto& t : b.edges) s.edge_labels.push_back(edge_label(g, t));
    s.where = spec.where + " block '" + s.name + "'";
    s.shape_where = s.mesh_where = s.zones_where = s.where;
    s.material_where = spec.material_where;
    blocks.push_back(std::move(s));
  }
  if (out) *out = std::move(rm);
  return blocks;
}

}  // namespace rockdem
