#pragma once
// The boundary kind "seismic": where a stage's ground motions enter the model. A compliant base
// (the default) is a quiet boundary with the motions' stress input (quiet_condition.hpp); a rigid
// base prescribes the motions' velocity to its gridpoints or rigid block.
#include "framework/boundary/conditions.hpp"

namespace rockdem {

// Rigid base: every selected gridpoint (or the rigid block, without spin) moves with the sum of
// the stage's motions, each along its direction; components without a motion are held at zero.
// The record is taken as the motion of the base itself (a within motion); an outcrop record at a
// rigid base is applied as it is, which the description states.
class RigidBaseCondition final : public BoundaryCondition {
 public:
  RigidBaseCondition(FaceSelection sel, bool rigid_block) : sel_(std::move(sel)), rigid_(rigid_block) {}
  std::string describe(const Model& m) const override;
  void setup(Model& m) override;
  void velocities(Model& m, double t) override;
  void set_motions(const std::vector<StageMotion>& motions) override { motions_ = motions; }
  bool takes_motions() const override { return true; }
  double history_duration() const override;
  bool renumber(const Renumbering& r) override { return rockdem::renumber(sel_, r); }

 private:
  FaceSelection sel_;
  bool rigid_;
  std::vector<StageMotion> motions_;
};

}  // namespace rockdem
