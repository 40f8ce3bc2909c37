#pragma once
// The results of a drift-stability study ([drift] in a case; docs/drift-study.md): at the end of
// the reference stage (the model in equilibrium after the excavation) and of every stage after it
// (the earthquakes and the returns to equilibrium between them), measured from the reference:
// joint slip and opening per joint set, hydraulic apertures and the equivalent permeability of the
// rock around the drift, blocks that detached and fell, the drift's convergence and the extent of
// the loosened zone. Written to <out>/drift/: events.csv (one row per stage), fallen_blocks.csv,
// contacts_<n>_<stage>.csv (every joint contact: where, which set, slip, opening, aperture).
//
// Called on the process that holds the whole model (run_case collects it there), between steps;
// what it keeps from the reference travels in the stage checkpoints (saved_state/restore_state),
// so a restarted run counts from the same reference.
#include <array>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "framework/io/case_data.hpp"
#include "framework/io/checkpoint.hpp"

namespace rockdem {

class DriftResults {
 public:
  DriftResults(const Case& c, std::filesystem::path out);

  // The stage `index` has ended with the model's state in `m` and the engine's unbalanced-force
  // ratio `ratio` (a rest stage that ended at max_steps shows it above its target): write its
  // results (from the reference stage on; earlier stages are ignored).
  void stage_ended(const Model& m, std::size_t index, double ratio);

  // What a stage checkpoint carries: the reference state and the blocks counted as fallen now.
  CheckpointArrays saved_state() const;
  // Read back from a stage checkpoint's arrays; the rows of events.csv written before it are kept.
  void restore_state(const CheckpointArrays& a, std::size_t stages_completed);

  // One row of events.csv (public for tests).
  struct Row {
    std::size_t stage = 0;
    std::string name, kind;
    double time = 0.0;
    std::map<std::string, double> values;  // by column name
  };
  const std::vector<Row>& rows() const { return rows_; }

 private:
  bool has_fallen(BlockId id) const;  // counted as fallen at the last stage end
  struct Reference {
    std::map<ContactKey, std::pair<double, double>> contacts;  // u_s, u_n at the reference
    std::map<BlockId, Vec2> centroids;                          // block centroids at the reference
    // The far field: gridpoints farther than `near` from the wall (block id, local index, position
    // at the reference), whose rigid motion since is the frame the results are measured in.
    std::vector<BlockId> far_block;
    std::vector<LocalIndex> far_local;
    std::vector<Vec2> far_x;
    // The wall points (crown, invert, left and right springlines): the nearest boundary gridpoint
    // of a remaining block, by its block id and local index, and its position at the reference.
    std::array<BlockId, 4> wall_block{};
    std::array<LocalIndex, 4> wall_local{};
    std::array<Vec2, 4> wall_x{};
    std::array<bool, 4> wall_found{};
    std::array<double, 3> k{};  // permeability kxx, kyy, kxy at the reference [m^2]
    bool taken = false;
  };
  struct Fallen {
    BlockId id{};
    std::string name;
    double area = 0.0, displacement = 0.0;
    std::size_t stage = 0;
  };

  void take_reference(const Model& m);
  // One joint contact's results (a row of contacts_*.csv, a point of joints_*.vtu).
  struct JointRecord {
    Vec2 x = Vec2::Zero(), normal = Vec2::Zero();
    int set = 0;    // index into sets_
    int state = 0;  // 0 elastic, 1 slipping, 2 open
    double wall = 0;  // distance to the drift's wall [m]
    double slip = 0, opening = 0, aperture = 0, length = 0, sigma_n = 0, tau = 0;
    double flow_length = 0;  // its share of the joint's length for the flow (flow_length())
  };
  std::vector<JointRecord> joint_records(const Model& m) const;
  // `moved`: each block's centroid displacement since the reference, in the far field's frame
  // (NaN for a block made since), in m.blocks order.
  void write_files(const Model& m, std::size_t index, const std::vector<JointRecord>& joints,
                   const std::vector<Vec2>& moved) const;
  void write_vtk(const Model& m, std::size_t index, const std::vector<JointRecord>& joints,
                 const std::vector<Vec2>& moved) const;
  double distance_to_wall(const Vec2& p) const;
  std::vector<std::string> columns() const;
  // A contact's slip and opening since the reference (from zero for a contact made since).
  std::pair<double, double> since_reference(const Contact& c) const;

  const Case& c_;
  std::filesystem::path dir_;
  std::vector<std::string> sets_;  // joint-set names in the contact store's label order
  Vec2 centre_ = Vec2::Zero();
  double radius_ = 0.0;  // of the circle with the opening's area [m]
  std::array<Vec2, 4> wall_points_{};
  Reference ref_;
  std::vector<Fallen> fallen_;
  std::vector<Row> rows_;
};

}  // namespace rockdem
