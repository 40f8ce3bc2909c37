#include "framework/io/block_inspection.hpp"

#include <fstream>
#include <map>

#include "framework/core/error.hpp"
#include "framework/core/units.hpp"
#include "framework/io/rock_mass_reader.hpp"
#include "framework/io/toml_values.hpp"
#include "framework/io/vtk_output.hpp"

namespace rockdem {

std::string write_blocks_for_inspection(const Case& c, const std::string& case_file, const std::filesystem::path& dir) {
  const Model& m = c.model;
  RockMass rm;
  std::map<std::string, const RockMassBlock*> generated;
  std::vector<BlockSpec> specs;
  if (!case_file.empty()) {
    // The case as it was read, with what the command line changed in it (--seed draws other
    // blocks than the file's seed): the traces must be those of the blocks built.
    const toml::table root = c.source_toml.empty() ? parse_toml_file(case_file, "case file") : toml::parse(c.source_toml, case_file);
    if (const auto* t = root["rock_mass"].as_table()) specs = rock_mass_blocks(read_rock_mass(*t, case_file), &rm);
  }
  for (std::size_t i = 0; i < specs.size(); ++i) generated[specs[i].name] = &rm.blocks[i];
  std::filesystem::create_directories(dir);
  std::vector<int> region, opening;
  const std::string csv_path = (dir / "blocks.csv").string();
  std::ofstream csv(csv_path);
  if (!csv) throw InputError("--write-blocks: cannot write '" + csv_path + "'");
  csv << "id,name,group,rigid,region,opening,vertices,area_m2,centroid_x_m,centroid_y_m\n";
  for (const Block& b : m.blocks) {
    const auto it = generated.find(b.name);
    region.push_back(it == generated.end() ? -1 : it->second->region);
    opening.push_back(it == generated.end() ? -1 : it->second->opening);
    Polygon p;
    for (int g : b.boundary) p.push_back(m.gp[static_cast<std::size_t>(g)].x0);
    const Vec2 centre = polygon_centroid(p);
    csv << b.id << "," << b.name << "," << m.contacts.group_names[static_cast<std::size_t>(b.group)] << ","
        << (b.rigid ? 1 : 0) << "," << region.back() << "," << opening.back() << "," << p.size() << ","
        << round_trip_text(signed_area(p)) << "," << round_trip_text(centre.x()) << "," << round_trip_text(centre.y())
        << "\n";
  }
  write_block_outlines_vtu(m, region, opening, (dir / "blocks.vtu").string());
  write_joint_traces_vtu(rm.segments, (dir / "traces.vtu").string());
  return "wrote " + std::to_string(m.blocks.size()) + " blocks (" + std::to_string(specs.size()) + " from [rock_mass], " +
         std::to_string(rm.slivers_merged) + " slivers merged, " + std::to_string(rm.holes_split) +
         " faces with holes split) and " + std::to_string(rm.segments.size()) + " joint segments to " + dir.string();
}

}  // namespace rockdem
