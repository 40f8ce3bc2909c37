#pragma once
// Builds a Case (model, engine settings, boundary conditions, stages, histories, outputs) from
// plain specs (case_spec.hpp), without any file format. The case reader hands it each entry of a
// case file as soon as it has read it, so mistakes in different entries are reported in the
// order they are written;
// code that makes its specs itself (e.g. a rock-mass generator) calls build_case().
//
// The parts must come in this order, each at most once unless it says "add": model_settings,
// time, add_material, add_joint, add_block, finish_blocks, in_situ, add_motion, add_boundary, add_stage, finish_stages,
// add_history, direct_shear, output, finish. Every mistake is an InputError naming the spec's
// `where` for it.
#include <map>
#include <set>
#include <string>
#include <vector>

#include "framework/io/case_data.hpp"
#include "framework/io/case_spec.hpp"

namespace rockdem {

class CaseBuilder {
 public:
  CaseBuilder(const std::string& file, const std::string& title);

  void model_settings(const ModelSettingsSpec& s);
  void time(const TimeSpec& s);
  void add_material(const MaterialSpec& s);
  void add_joint(const JointSpec& s);
  void add_block(const BlockSpec& s);
  // No blocks, blocks that overlap and joints between groups no block has are mistakes.
  void finish_blocks();
  // The in-situ stress field; a field that does not balance the model's gravity (a density other
  // than the blocks', a gradient without gravity, a datum below the top of the model) is a mistake.
  void in_situ(const InSituSpec& s);
  // A [[motions]] entry: its record read, processed and checked against the mesh (after the blocks).
  void add_motion(const MotionSpec& s);
  void add_boundary(const BoundarySpec& s);
  void add_stage(const StageInput& s);
  // No stages, and conditions naming stages that do not exist, are mistakes. Free-field columns
  // whose top is not as the model's top in a stage they share are warned of (Case::warnings).
  void finish_stages();
  void add_history(const HistoryInput& s);
  void direct_shear(const DirectShearInput& s);
  void drift(const DriftInput& s);
  void output(const OutputSpec& s);
  Case finish();

 private:
  void add_region_boundary(const BoundarySpec& s);
  void resolve_excavation(const StageInput& s, StageSpec& stage);
  void resolve_motions(const StageInput& s, StageSpec& stage) const;
  // Every stage's motions are taken by a condition active in it, of a type it can take.
  void check_stage_motions();
  // Quiet and free-field conditions, kept for check_column_tops.
  void note_column_top(const BoundarySpec& s, const std::vector<FaceSelection>& selections);
  void check_column_tops();
  int excavated_by(int block) const;
  static int component_index(const HistoryQuantity& q, const HistoryInput& s);
  int group_index(const std::string& group);
  int material_index(const BlockSpec& s) const;
  void check_overlaps() const;
  void label_edges(const BlockSpec& s, const Polygon& shape, const std::vector<int>& corners);
  std::vector<int> joint_labels(const JointSpec& s) const;
  void assign_joint_groups();
  std::string stage_list() const;

  Case c_;
  std::map<std::string, int> materials_;  // name -> index in Model::materials
  std::map<std::string, int> groups_;     // block group -> index
  std::vector<JointSpec> joints_;         // index = joint model; kept for stage changes
  std::set<std::string> stage_names_;
  std::map<std::string, std::string> scale_off_wheres_;  // stage name -> where its scale_off was written
  // Conditions that name a block (not a region): a stage that excavates it must come after them.
  struct NamedCondition {
    int block;
    std::vector<std::string> stages;
    std::string where;
  };
  std::vector<NamedCondition> named_conditions_;
  // Conditions on a region (a line or box), with the blocks it took gridpoints of: an excavation
  // may take some of them away, not all (nor any of a spanning condition's, a free-field column).
  struct RegionCondition {
    std::vector<int> blocks;
    bool spanning = false;
    std::vector<std::string> stages;
    std::string where;
  };
  std::vector<RegionCondition> region_conditions_;
  void check_region_conditions();
  bool acts_from(const std::vector<std::string>& stages, std::size_t k) const;
  std::set<std::string> edge_joint_names_;  // joint sets and named joints that block edges lie on
  // The quiet and free_field [[boundary]] entries, in the order given: whether a free-field
  // column's top matches the model's top is a question about both, answered once the stages are known.
  struct TopCondition {
    bool free_field = false;  // else quiet
    bool quiet_top = false;   // free_field: top = "quiet"
    std::vector<FaceSelection> selections;
    std::vector<std::string> stages;
    std::string where;
  };
  std::vector<TopCondition> top_conditions_;
};

// A whole case from specs made in code.
Case build_case(const CaseSpec& spec);

}  // namespace rockdem
