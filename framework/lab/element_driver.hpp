#pragma once
// Single-joint element driver: one joint point (a JointModel, the very object the DEM engine
// uses for a contact) driven through a direct-shear path, as in a laboratory direct shear test.
// Normal condition per stage: constant normal stress (CNL; du_n is solved each increment by
// secant iteration on copies of the state) or constant normal stiffness (CNS; a spring of
// stiffness K resists the dilation). Shear paths: cycles, sinusoid, or a (time, displacement)
// table. Stages run in sequence on one specimen, the law state (wear) carried from stage to
// stage. Results are rows of the measurement format. Nothing allocates per step except the
// output rows, which are reserved beforehand.
// Optional compliant loading frame (frame_stiffness > 0): the path then drives the frame's load
// point, and the top block (mass per unit joint area frame_mass) moves between the frame spring
// and the joint, m u'' = k_f (u_load - u) - tau(u), integrated by backward Euler (unconditionally
// stable; it damps the stiff joint mode, not the frame's). A soft frame lets a velocity-weakening
// joint stick and slip, as in the report's dynamic tests; off by default (the joint offset is the
// path itself, exactly as without the option).
#include <string>
#include <vector>

#include "framework/io/measurement_csv.hpp"
#include "framework/plugin_api/joint_law.hpp"

namespace rockdem {

// Shear displacement history of one stage, as offsets from the mated position [m].
struct ShearPath {
  enum class Kind { cycles, sinusoid, table };
  Kind kind = Kind::cycles;
  double amplitude = 0.0;  // [m]
  int count = 1;           // number of cycles
  double velocity = 0.0;   // cycles: shear velocity [m/s]
  double frequency = 0.0;  // sinusoid [Hz]
  bool one_sided = false;  // cycles: 0 -> +A -> 0 instead of 0 -> +A -> 0 -> -A -> 0
  std::vector<double> time, disp;  // table: time [s] (relative to the stage start), offset [m]
  std::string source;              // table: the file it was read from (for a DEM run of the same path)

  // One cycle is 0 -> +A -> 0 -> -A -> 0 (or 0 -> +A -> 0 when one_sided) at constant velocity.
  static ShearPath cycles(double amplitude, int number, double velocity, bool one_sided = false);
  // u(t) = A sin(2 pi f t) for `cycles` periods.
  static ShearPath sinusoid(double amplitude, double frequency, int cycles);
  // Piecewise linear through (time, offset) points; time must not decrease.
  static ShearPath table(std::vector<double> time_s, std::vector<double> disp_m);
};

enum class NormalControl { constant_stress, constant_stiffness };

struct ElementStage {
  double normal_stress = 0.0;  // CNL target, or CNS initial normal stress [Pa]
  NormalControl control = NormalControl::constant_stress;
  double normal_stiffness = 0.0;  // CNS spring stiffness [Pa/m]
  ShearPath path;
  // Optional model for this stage (same law and effects, other parameter values, e.g. Table 4-2's
  // per-stage values); null = the driver's model. The state is carried over unchanged.
  const JointModel* model = nullptr;
};

struct ElementOptions {
  double max_step = 1e-5;     // largest shear displacement increment [m]
  double length = 1.0;        // joint length handed to the law [m]
  int output_every = 1;       // write every n-th increment (always: each stage's last, each reversal, stop and restart of the path)
  double tolerance = 1e-10;   // relative tolerance of the normal condition
  int max_iterations = 60;    // per increment, for the normal solve
  double frame_stiffness = 0.0;  // loading frame spring per unit joint area [Pa/m]; 0 = rigid (off)
  double frame_mass = 0.0;       // top-block mass per unit joint area [kg/m^2]; needed with a frame
  bool extra_columns = true;     // record dilation_mm and dissipated_J_per_m2 (a fit's runs read neither)
};

class ElementDriver {
 public:
  explicit ElementDriver(const JointModel& model, ElementOptions options = {});

  // Back to the virgin joint (state initialised, time, offsets and energy zero).
  void reset();
  // Runs the stages in sequence on the current state and appends rows to `out` (creating the
  // extra columns dilation_mm and dissipated_J_per_m2 if `out` has none yet). Stages are
  // numbered from first_stage_number.
  void run(const std::vector<ElementStage>& stages, MeasurementFile& out, int first_stage_number = 1);
  MeasurementFile run(const std::vector<ElementStage>& stages);

  // Starts a stage: applies its normal stress with no shear (normal loading), zeroes the stage's
  // normal-displacement reference. Then call step() for each shear increment.
  const JointResponse& begin_stage(const ElementStage& stage);
  // One shear increment du_s over dt under the stage's normal condition (time advances by dt;
  // run() instead sets it from the path's own times, so segment ends are exact).
  const JointResponse& step(const ElementStage& stage, double du_s, double dt);

  const JointStateBlock& state() const { return state_; }
  const JointResponse& response() const { return r_; }
  double time() const { return time_; }
  double dissipated() const { return dissipated_; }        // cumulative [J/m^2]
  double normal_disp() const { return u_n_ - u_n_stage_; }  // since the stage start [m]
  double load_point() const { return frame() ? u_load_ : r_.u_s; }  // where the path drives [m]
  double block_velocity() const { return v_block_; }            // with a frame [m/s]
  long steps() const { return steps_; }
  long unconverged_steps() const { return unconverged_; }  // normal condition not met (tolerance, or a false root)

  // Number of increments a stage's path takes (used to reserve output rows).
  long count_increments(const ShearPath& path) const;

 private:
  const JointModel& model_for(const ElementStage& s) const { return s.model ? *s.model : model_; }
  bool frame() const { return opt_.frame_stiffness > 0.0; }
  // scan = false skips the costly last search (see step()).
  void solve_normal(const ElementStage& stage, double du_s, double dt, bool scan = true);
  // solve_normal, halving the increment (down to 1/64) where it cannot meet the normal condition.
  bool solve_substepped(const ElementStage& stage, double du_s, double dt, int depth, bool may_split = true);
  void frame_step(const ElementStage& stage, double du_load, double dt);
  // The driver's state, to try an increment and go back.
  struct Snapshot {
    JointStateBlock state;
    JointResponse r;
    double time, dissipated, u_n, last_du_n, last_slope;
    long steps, unconverged;
  };
  Snapshot snapshot() const { return {state_, r_, time_, dissipated_, u_n_, last_du_n_, last_slope_, steps_, unconverged_}; }
  void restore(const Snapshot& s);
  void append_row(MeasurementFile& out, int stage) const;

  const JointModel& model_;
  ElementOptions opt_;
  JointStateBlock state_{};
  JointResponse r_{};
  double time_ = 0.0;
  double dissipated_ = 0.0;
  double u_n_ = 0.0;        // normal displacement since the start [m]
  double u_n_stage_ = 0.0;  // at the start of the current stage (after normal loading)
  double cns_sigma0_ = 0.0, cns_u_n0_ = 0.0;
  double last_du_n_ = 0.0;
  double last_slope_ = 0.0;  // dg/d(du_n) where the last solve met the condition (0: none yet)
  long steps_ = 0, unconverged_ = 0;
  // The last increment missed the normal condition even in halves: the next ones skip the scan
  // and the halving (but every 16th) until one meets it.
  bool hopeless_ = false;
  long skipped_ = 0;
  double u_load_ = 0.0, v_block_ = 0.0;  // frame load point [m] and block velocity [m/s]
};

}  // namespace rockdem
