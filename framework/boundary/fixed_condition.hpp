#pragma once
// The boundary kind "fixed": gridpoints (or a whole rigid block) held in place.
#include "framework/boundary/conditions.hpp"

namespace rockdem {

// Gridpoints held in x and/or y (or a whole rigid block held in place).
class FixedCondition final : public BoundaryCondition {
 public:
  FixedCondition(FaceSelection sel, bool fix_x, bool fix_y, bool whole_rigid_block);
  std::string describe(const Model& m) const override;
  void setup(Model&) override;
  void velocities(Model&, double) override;

  bool renumber(const Renumbering& r) override { return rockdem::renumber(sel_, r); }

 private:
  FaceSelection sel_;
  bool fx_, fy_, rigid_;
};

}  // namespace rockdem
