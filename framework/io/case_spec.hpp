#pragma once
// A DEM case as plain data: what the case reader (case_reader.hpp) makes of each table of a case
// file, and what the case builder (case_builder.hpp) turns into a Model, boundary conditions,
// stages and histories. Nothing here knows TOML, so specs can also be made in code (e.g. by a
// rock-mass generator) and built the same way. Values are in SI units.
//
// Members named `where` or `*_where` are the places messages name when the builder finds a
// mistake ("case.toml:12 key 'blocks.top.material'", "case.toml:9 [boundary]"); the reader
// writes them as the case-file messages always read, code that makes specs writes whatever tells
// its user where the value came from.
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "framework/boundary/condition_kinds.hpp"
#include "framework/boundary/region.hpp"
#include "framework/core/params.hpp"
#include "framework/geometry/polygon.hpp"
#include "framework/io/case_data.hpp"
#include "framework/model/contact.hpp"
#include "framework/plugin_api/joint_law.hpp"
#include "framework/seismic/input_motion.hpp"

namespace rockdem {

// [model]
struct ModelSettingsSpec {
  double rounding = 0.5e-3;   // [m]
  double tolerance = 1e-3;    // detection tolerance [m]
  std::optional<Vec2> gravity;
};

// [time]: the engine settings that a case sets (the defaults are EngineSettings').
struct TimeSpec {
  double dt_safety = 0.5, fixed_dt = 0.0, mass_scaling_dt = 0.0;
  int refresh_interval = 10;
  double velocity_limit = 1e3;
};

// [[materials]]: a rock material by model name and parameter values.
struct MaterialSpec {
  std::string name, model;
  RawValues params;
  std::string where, model_where;
};

// [[joints]]: a joint law with effects, acting between two block groups ("*": any); with
// joint_sets and/or bridges, only at edges of rock-mass blocks with those labels (EdgeLabel):
// the traces of the named sets and joints, or (bridges = true) their rock bridges, or with no
// joint_sets every bridge and glued cut. Such an assignment wins over the group ones.
struct JointSpec {
  std::string name, law;
  std::array<std::string, 2> between{"*", "*"};
  std::vector<std::string> joint_sets;
  bool bridges = false;
  std::string joint_sets_where;
  RawValues params;
  std::vector<EffectSpec> effects;
  std::string law_where;
  std::string calibration;  // the calibrate/diagnose JSON the law, parameters and effects came from
};

// [[blocks]]: a rigid block or a meshed deformable one.
struct BlockSpec {
  struct Rectangle {
    double x0 = 0, y0 = 0, width = 0, height = 0;
  };
  enum class Mesh { structured, unstructured };
  std::string name, group;  // group: defaults to the name
  bool rigid = true;
  std::optional<Rectangle> rectangle;  // the shape: a rectangle, or else `polygon`
  Polygon polygon;
  double density = 0.0;                // rigid blocks [kg/m3]
  std::string material;                // deformable blocks: a [[materials]] name
  std::optional<std::array<int, 2>> zones;  // rectangles: nx, ny zones; else `zone_size`
  double zone_size = 0.0;                   // [m]
  Mesh mesh = Mesh::structured;
  // Per polygon edge i (polygon[i] to polygon[i + 1]): what it lies on (rock-mass blocks), or
  // nothing; empty for hand-written blocks.
  std::vector<std::optional<EdgeLabel>> edge_labels;
  std::string where, shape_where, material_where, zones_where, mesh_where;
};

// [in_situ]: the stress field the model starts from (framework/model/stress_field.hpp).
struct InSituSpec {
  std::optional<double> surface;  // y of the datum [m]; default the top of the model
  std::optional<double> density;  // [kg/m3]; default the blocks' (which must then agree)
  double surcharge = 0.0;         // vertical stress at the datum, compression positive [Pa]
  double k = 1.0;                 // sigma_H / sigma_v
  double sxy = 0.0;               // tension-positive convention [Pa]
  std::string where, surface_where, density_where;
};

// [[motions]]: a recorded ground motion and how it is processed into a model's input
// (framework/seismic/input_motion.hpp; keys in docs/case-files.md).
struct MotionSpec {
  std::string name;
  std::string file;                // path as resolved against the case's folder
  std::string format = "auto";     // auto (by extension and content), columns, csv, peer_at2
  seismic::RecordLayout layout;    // column, time column or dt, unit
  seismic::MotionType type = seismic::MotionType::outcrop;
  int direction = 0;               // 0: x, 1: y
  seismic::DisplacementProcessing processing;
  seismic::MotionScaling scaling;
  bool refuse_above_mesh = false;  // above_mesh = "refuse" (else "filter": low-pass at the mesh limit)
  double zones_per_wavelength = 10.0;
  std::string where, file_where, filter_where;
};

// [[boundary]]: a condition of a registered kind (framework/boundary/condition_kinds.hpp) on a
// block's face, with the values of the kind's keys.
struct BoundarySpec {
  std::string type, block;  // block empty: the condition acts on `region`
  std::optional<Region> region;  // box or line: every boundary gridpoint in it, any block
  std::string region_where;
  std::string face = "all";
  bool face_given = false;
  std::map<std::string, ConditionValue> values;
  std::vector<std::string> stages;  // empty: all
  std::string where, type_where, block_where, face_where;
};

// [[stages]]: the stage as run, and the joints whose parameters change from it on.
struct StageInput {
  struct JointChange {
    std::string joint;
    RawValues params;  // only the parameters that change
    std::string where;
  };
  StageSpec stage;  // joint_models left empty: the builder makes them from `joint_changes`
  std::vector<JointChange> joint_changes;
  // Ground motions the stage plays from its start ([[motions]] names), and their scaling for this
  // stage (a factor, or a target peak of the first motion, the others keeping their ratio to it).
  std::vector<std::string> motions, motion_wheres;
  seismic::MotionScaling motion_scaling;
  std::string motion_scaling_where;  // the motion_scale, pga or pgv key ("" when none)
  // Block or group names the stage excavates, with where each was written.
  std::vector<std::string> excavate, excavate_wheres;
  std::string scale_off_where;  // "" when the stage has no scale_off
};

// [[histories]]
struct HistoryInput {
  std::string name, quantity, block, face;
  std::optional<std::string> component;  // default x
  std::optional<std::string> unit;       // default the quantity's
  std::string description;
  double scale = 1.0;
  std::string quantity_where, block_where, component_where, face_where;
  std::optional<Vec2> at, to;  // quantities by location [m]
  std::string at_where, to_where;
};

// [direct_shear]: blocks by name; see DirectShearSpec.
struct DirectShearInput {
  std::string specimen;
  double joint_length = 0.0;
  std::string loader, top, bottom;
  std::vector<std::string> other_loaders, other_loader_wheres;
  std::vector<std::string> shear_stages;
  std::vector<double> normal_stresses;
  std::string where, loader_where, top_where, bottom_where;
};

// [drift]: the results of a drift-stability study (DriftSpec); names as written.
struct DriftInput {
  std::string opening, reference_stage;
  double near = 0.0, initial_aperture = 0.0, residual_aperture = 0.0, fall_displacement = 0.0, loosened = 0.0;
  std::string where, opening_where, reference_where;
};

// A whole case, in the order the builder takes its parts.
struct CaseSpec {
  std::string file;  // named by messages about the case as a whole
  std::string title = "untitled";
  ModelSettingsSpec model;
  std::optional<TimeSpec> time;
  std::vector<MaterialSpec> materials;
  std::vector<JointSpec> joints;
  std::vector<BlockSpec> blocks;
  std::optional<InSituSpec> in_situ;
  std::vector<MotionSpec> motions;
  std::vector<BoundarySpec> boundaries;
  std::vector<StageInput> stages;
  std::vector<HistoryInput> histories;
  std::optional<DirectShearInput> direct_shear;
  std::optional<DriftInput> drift;
  std::optional<OutputSpec> output;
};

}  // namespace rockdem
