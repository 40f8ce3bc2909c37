#pragma once
// Boundary conditions. Each acts on a set of gridpoints (a block face) or on a rigid block, may be
// limited to some stages, and is applied by the engine at fixed points of each cycle:
//   setup()     once per stage: flags fixed/prescribed degrees of freedom;
//   forces()    adds external forces (tractions, dashpots) to GridPoint::f and returns the sum
//               of their magnitudes (the unbalanced-force ratio is measured against it);
//   velocities() overwrites prescribed velocities after the equation of motion.
#include <memory>
#include <string>
#include <vector>

#include "framework/boundary/time_function.hpp"
#include "framework/seismic/input_motion.hpp"
#include "framework/model/excavation.hpp"
#include "framework/model/model.hpp"

namespace rockdem {

// Boundary gridpoints of a block on the face(s) whose outward normal lies within 10 degrees of
// `direction`, and the boundary edges (loop positions) they belong to.
struct FaceSelection {
  int block = 0;
  std::vector<int> points;  // gridpoint indices
  std::vector<int> edges;   // positions i in the block's boundary loop (edge i -> i+1)
};
FaceSelection select_face(const Model& m, int block, const Vec2& direction);
// Calls f(ga, gb, d) for each selected edge: its two gridpoints (counter-clockwise) and the vector
// from the first to the second (the outward normal times the length is (d.y, -d.x)).
// In a decomposed run only the process owning the block calls f (partition.hpp).
template <class F>
void for_each_edge(Model& m, const FaceSelection& sel, F&& f) {
  if (!m.part.owns(sel.block)) return;
  const Block& b = m.blocks[static_cast<std::size_t>(sel.block)];
  const int n = static_cast<int>(b.boundary.size());
  for (int i : sel.edges) {
    const int ga = b.boundary[static_cast<std::size_t>(i)], gb = b.boundary[static_cast<std::size_t>((i + 1) % n)];
    f(ga, gb, Vec2(m.gp[gb].x - m.gp[ga].x));
  }
}
// Face names: "top" (+y), "bottom" (-y), "left" (-x), "right" (+x); "all" selects every
// boundary point. Throws InputError listing the valid names.
Vec2 face_direction(const std::string& name, const std::string& where);
// A selection after blocks were removed (excavation): new gridpoint and block positions; false if
// its block was removed (the edges, positions in the block's boundary loop, do not change).
bool renumber(FaceSelection& sel, const Renumbering& r);

class BoundaryCondition {
 public:
  virtual ~BoundaryCondition() = default;
  // One line for progress output, naming the block.
  virtual std::string describe(const Model& m) const = 0;
  virtual void setup(Model&) {}
  virtual double forces(Model&, double /*stage_time*/) { return 0.0; }
  virtual void velocities(Model&, double /*stage_time*/) {}
  // Time after which the condition's prescribed histories are finished (0: none ends). A stage
  // with duration = "auto" runs as long as the longest of its active conditions'.
  virtual double history_duration() const { return 0.0; }
  // After an excavation: the new positions of its gridpoints and block. A condition whose block
  // was removed returns false, is marked `removed` and is never active again.
  virtual bool renumber(const Renumbering&) { return true; }
  bool removed = false;
  // The ground motions the stage about to start plays (its `motion` key), each with the stage's
  // scale factor; called before setup() at every stage start, with none for a stage without.
  // Conditions that apply seismic input (seismic_condition.cpp, free_field_condition.cpp) keep them.
  struct StageMotion {
    const seismic::InputMotion* motion = nullptr;
    double factor = 1.0;
  };
  virtual void set_motions(const std::vector<StageMotion>&) {}
  virtual bool takes_motions() const { return false; }
  // After velocities(), once per step: conditions with a dynamic state of their own (the free
  // field's column) advance it by the step's dt.
  virtual void end_step(const Model&, double /*dt*/) {}
  // A stage starts in which this condition does not act. Conditions that hold the static forces of
  // the stage before their first one forget them, so that acting again after stages under other
  // conditions (an earthquake after a return to equilibrium on fixed boundaries) they take the
  // forces of the stage just before that one, not the stale ones.
  virtual void deactivated() {}
  // State a condition carries from stage to stage (forces held since a stage's start, a free-field
  // column's motion), written into checkpoints so a restarted run continues it exactly. Empty:
  // nothing to keep.
  virtual std::vector<double> saved_state() const { return {}; }
  virtual void restore_state(const std::vector<double>&) {}
  // Viscous conditions add the dashpot coefficient [N s/m per m] each of their gridpoints feels
  // to `c` (indexed like Model::gp): explicit dashpots are stable only for dt < 2 m / c, which
  // the engine's time step then respects (a rigid block with a quiet face has a large mass but
  // also a large dashpot, and its contact stiffness alone would allow too long a step).
  virtual void add_dashpots(const Model&, std::vector<double>& /*c*/) const {}
  // Stages this condition is active in (empty: all).
  std::vector<std::string> stages;
  bool active_in(const std::string& stage) const;
};

}  // namespace rockdem
