#pragma once
// VTK output for ParaView: per output step, blocks_<step>.pvtu and contacts_<step>.pvtu, each a
// parallel unstructured grid whose pieces blocks_<step>_<p>.vtu (XML unstructured grids, binary
// appended, zlib-compressed) are written by the processes of the run, one each (process p: the
// blocks it owns and the contacts of their points; a serial run writes one piece, _0), plus
// blocks.pvd and contacts.pvd collections listing every step's .pvtu with its time. No process
// gathers the model for a field output. The .pvd files are rewritten after each step so that an
// interrupted run still opens in ParaView.
//
// Array names carry their unit (SI); integer categories have their names in field-data string
// arrays. docs/user-guide-output.md lists them for users.
// blocks_<step>.vtu: points are all gridpoints (z = 0); deformable blocks contribute their zones as
//   VTK_TRIANGLE cells, rigid blocks one VTK_POLYGON cell over their boundary loop.
//   point data: displacement_m (x - x0), velocity_m_per_s (3 components, z = 0, ready for Warp By
//               Vector)
//   cell data:  stress_Pa (6-component symmetric tensor XX YY ZZ XY YZ XZ, tension positive: a
//               zone's own; a rigid block's mean stress from its boundary forces with ZZ = 0,
//               NaN for a held one or before the first step), stress_from (1 zone, 2 rigid block's
//               forces, 0 none), block_id, block_name, rigid (0/1), group, process
//   field data: group_names, stress_from_names
// contacts_<step>.vtu: one VTK_VERTEX per contact point at the contact gridpoint's position.
//   point data: normal_stress_Pa, shear_stress_Pa (compression positive), shear_displacement_m,
//               normal_displacement_m (opening positive), state (0 elastic, 1 slipping, 2 open),
//               length_m, normal (3 components), point_block, other_block, joint,
//               edge_label (the rock-mass label of the other block's edge, -1 none), bridge (1 rock
//               bridge or glued cut, 0 joint trace, -1 no label), process
//   field data: state_names, joint_names, edge_label_names
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "framework/geometry/rock_mass.hpp"

namespace rockdem {

struct Model;
class Communication;

class VtkSeries {
 public:
  struct Entry {
    double time;
    long step;
    std::string file;  // relative to the output folder
  };

  // Creates `dir` if needed. With `contacts` false no contacts_* files are written.
  explicit VtkSeries(std::filesystem::path dir, bool contacts = true);

  // Writes one output step of `m` (at m.time, m.step) and rewrites the .pvd files. Writing the
  // same step twice replaces its entry (e.g. the final state after a periodic output). In a
  // decomposed run every process calls it (each writes its piece; process 0 then the .pvtu and
  // .pvd files); a failure on any process is raised on all of them.
  void write(const Model& m, const Communication& comm);
  void write(const Model& m);  // a serial model: one piece

  // After a restart at `time`: keep the steps of an earlier run in `dir` up to `time` (read from
  // its blocks.pvd/contacts.pvd if present) so that the collection covers the whole history.
  void resume(double time);

  const std::filesystem::path& dir() const { return dir_; }
  const std::vector<Entry>& block_steps() const { return blocks_; }
  const std::vector<Entry>& contact_steps() const { return contacts_; }

 private:
  std::filesystem::path dir_;
  bool write_contacts_;
  std::vector<Entry> blocks_, contacts_;
};

// The two grids as standalone writers (used by VtkSeries; handy for one-off snapshots): the
// blocks this process owns (every block of a serial model) and the contacts of their points.
void write_blocks_vtu(const Model& m, const std::string& path);
void write_contacts_vtu(const Model& m, const std::string& path);

// Named fields for results that are not the model's own state (the drift study's joints and
// blocks, docs/drift-study.md): one value per point or per block, in the order given.
struct VtkFields {
  std::vector<std::pair<std::string, std::vector<double>>> scalars;
  std::vector<std::pair<std::string, std::vector<Vec2>>> vectors;  // written with z = 0
  std::vector<std::pair<std::string, std::vector<int>>> ints;
  // String arrays in the field data, e.g. the names that an int field's values index.
  std::vector<std::pair<std::string, std::vector<std::string>>> names;
};
// One VTK_VERTEX per point, `fields` as point data.
void write_points_vtu(const std::vector<Vec2>& points, const VtkFields& fields, const std::string& path);
// One VTK_POLYGON per block over its boundary loop at the gridpoints' present positions, `fields`
// as cell data (one value per block, in m.blocks order).
void write_block_cells_vtu(const Model& m, const VtkFields& fields, const std::string& path);
// A ParaView collection of `entries` (time and file, relative to the collection's folder), written
// to a temporary name and renamed.
void write_pvd_collection(const std::filesystem::path& path, const std::vector<VtkSeries::Entry>& entries);

// Inspection before a run (`rockdem run --write-blocks`): one polygon cell per block over its
// boundary loop, cell data block_id, group, rigid, region and opening (per block, -1 none).
void write_block_outlines_vtu(const Model& m, const std::vector<int>& region, const std::vector<int>& opening,
                              const std::string& path);
// The rock mass's interior edges as lines, cell data joint_set (RockMassSegment::tag.source),
// bridge (0 joint trace, 1 bridge or glued cut) and kind (EdgeKind: 0 joint, 1 bridge, 2 cut).
void write_joint_traces_vtu(const std::vector<RockMassSegment>& segments, const std::string& path);

}  // namespace rockdem
