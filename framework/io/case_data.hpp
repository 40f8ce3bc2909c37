#pragma once
// A DEM case as it is run: the Model, the Engine's settings, boundary conditions, stages,
// histories and outputs, as the case builder (case_builder.hpp) makes them. Apart from
// case.hpp so that the builder and code that makes cases need no TOML.
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "framework/boundary/conditions.hpp"
#include "framework/mechanics/engine_settings.hpp"
#include "framework/mechanics/history_quantities.hpp"
#include "framework/model/model.hpp"
#include "framework/model/stress_field.hpp"
#include "framework/seismic/input_motion.hpp"

namespace rockdem {

struct StageSpec {
  std::string name;
  Damping damping;
  enum class Until { equilibrium, duration, steps } until = Until::duration;
  double duration = 0.0;     // [s]; for `duration`
  bool auto_duration = false;  // duration = longest active velocity history
  long steps = 0;
  double ratio = 1e-5;       // unbalanced-force ratio for `equilibrium`
  // >0: `equilibrium` also needs every free rigid block's own ratio (its net force over the sum of
  // the forces on it) below this, so that one block falling into an opening, whose weight is a
  // tiny part of the model's forces, is not taken for equilibrium.
  double block_ratio = 0.0;
  long max_steps = 1000000;  // cap for `equilibrium`
  // `equilibrium` not reached within max_steps: stop the run (exit 3), or end the stage there
  // with a warning and go on (a drift whose loosened blocks keep moving is a result of a study).
  bool continue_at_max_steps = false;
  // Joint models put in force from this stage on (same law and effects, other parameter values;
  // the contacts keep their state): (index in ContactStore::models, model).
  std::vector<std::pair<int, std::shared_ptr<const JointModel>>> joint_models;
  // Excavation before the stage starts: the blocks removed (by Block::id) and the steps over
  // which the forces they exerted are released (0: at once).
  std::vector<BlockId> excavate;
  long relax_steps = 0;
  // >0 (`equilibrium` stages): scaling, as after a blast. A block that has moved further than this
  // [m] from where the stage found it (the mean of its gridpoints) is taken out of the model while
  // the stage runs, unless a boundary condition, a history or [direct_shear] names or holds it
  // (Case::held_blocks): a loose block in a drift's crown would otherwise keep the stage from its
  // equilibrium, and which blocks come loose depends on the realisation, not on names.
  double scale_off = 0.0;
  // Mass scaling in this stage: the stable time step masses are scaled to (0: real masses);
  // none: the case's [time] mass_scaling_dt.
  std::optional<double> mass_scaling_dt;
  // Ground motions played from the stage's start: (index in Case::motions, scale factor).
  struct Motion {
    int index = 0;
    double factor = 1.0;
  };
  std::vector<Motion> motions;
};

// One named history: a registered quantity (framework/mechanics/history_quantities.hpp) measured
// on its target and multiplied by `scale`.
struct HistorySpec {
  std::string name, unit, description;
  const HistoryQuantity* quantity = nullptr;
  HistoryTarget target;
  double scale = 1.0;
};

// Output in the measurement format for direct-shear cases (docs/measurement-format.md):
// shear stress = contact force of the loading block over the nominal joint length; shear
// displacement = loading-block displacement; normal displacement = mean vertical displacement of
// the top block's bottom gridpoints minus that of the bottom block's top gridpoints.
// A test of several normal-stress stages lists one shear stage per test stage; each is numbered in
// the file (1, 2, ...) with its shear and normal displacements measured from that stage's start.
struct DirectShearSpec {
  bool enabled = false;
  std::string specimen;
  double joint_length = 0.2032;
  int loader = -1, top = -1, bottom = -1;
  // Further loading blocks moving with `loader` (e.g. one on each side of the top block, each only
  // pushing): the shear force is the sum over all of them.
  std::vector<int> other_loaders;
  std::vector<int> top_face, bottom_face;
  std::vector<std::string> shear_stages;  // case stages whose samples are written, in test order
  std::vector<double> normal_stresses;    // applied on the top face in each, for the file [Pa]
  std::vector<std::pair<std::string, std::string>> metadata;  // extra '# key: value' lines
};

// [drift]: a drift-stability study's results, written at the end of the reference stage and of
// every stage after it (framework/simulation/drift_results.hpp, docs/drift-study.md).
struct DriftSpec {
  bool enabled = false;
  std::string opening;              // the opening's block name
  std::vector<Vec2> outline;        // its outline as built (counter-clockwise) [m]
  std::size_t reference_stage = 0;  // results count from the end of this stage (index)
  double near = 0.0;                // [m] the zone around the drift: within this of its wall
  double initial_aperture = 0.0;    // [m] hydraulic aperture of a joint at zero normal displacement
  double residual_aperture = 0.0;   // [m] the smallest hydraulic aperture (a closed joint)
  double fall_displacement = 0.0;   // [m] a block moved this far towards the drift has fallen
  double loosened = 0.0;            // [m] slip or opening that makes a joint part of the loosened zone
};

struct OutputSpec {
  long history_interval = 100;  // steps between history samples
  long vtk_interval = 0;        // steps between VTK frames (0: automatic, about 25 per stage)
  double progress_seconds = 2.0;
  // Not a case key: whether progress may update one line in place when the output is a terminal.
  // `rockdem run` turns it off under an MPI launcher, whose output forwarding gives every process
  // a pseudo-terminal whatever mpirun's own output is, so that a log would fill with carriage
  // returns and erase codes.
  bool updating_line = true;
  // Checkpoints within stages (checkpoint_step_<n>.h5), at the first contact detection after
  // every checkpoint_steps steps of the run or checkpoint_seconds of wall-clock time ([output]
  // checkpoint_every = "N steps" or "30 min"; 0: none); the newest checkpoint_keep of them are
  // kept (0: all). They do not change the run's results.
  long checkpoint_steps = 0;
  double checkpoint_seconds = 0.0;  // wall clock
  long checkpoint_keep = 3;
};

struct Case {
  std::string file;
  std::string title;
  Model model;
  EngineSettings settings;
  std::vector<std::unique_ptr<BoundaryCondition>> conditions;
  // [in_situ]: zones and contacts start from this field at the start of the run (not on restart).
  std::optional<StressField> in_situ;
  // [[motions]], processed (shared: conditions hold pointers to them while the case runs).
  std::vector<std::shared_ptr<const seismic::InputMotion>> motions;
  std::vector<StageSpec> stages;
  std::vector<HistorySpec> histories;
  DirectShearSpec direct_shear;
  DriftSpec drift;
  OutputSpec output;
  std::vector<std::string> block_names;
  // Blocks a [[boundary]] entry names or acts on, a [[histories]] entry names, or [direct_shear]
  // names (ids, sorted): a stage's scale_off never takes them out.
  std::vector<BlockId> held_blocks;
  // The case as it was read (TOML; --joint files in a table `--joint`), kept in checkpoints: a
  // restart compares it with its own (case_comparison.hpp).
  std::string source_toml;
  // What the builder found legal but most likely a mistake (free-field column tops unlike the
  // model's top), one message each, naming the entries: the command that runs the case prints
  // them as warnings, and the run goes on (a study may keep such a case on purpose).
  std::vector<std::string> warnings;
  int block_index(const std::string& name, const std::string& where) const;
};

}  // namespace rockdem
