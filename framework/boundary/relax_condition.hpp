#pragma once
// The forces removed blocks exerted on the blocks that remain, applied after an excavation and
// reduced linearly to zero over a number of steps (the "relax" of UDEC and FLAC), so that an
// opening is not made in one shock. Made by an excavation stage, not named in case files.
#include <utility>
#include <vector>

#include "framework/boundary/conditions.hpp"

namespace rockdem {

class RelaxCondition final : public BoundaryCondition {
 public:
  // `forces`: (gridpoint, force [N/m]) as the removed blocks pushed on it at the excavation.
  RelaxCondition(std::vector<std::pair<int, Vec2>> forces, long steps);
  std::string describe(const Model& m) const override;
  // Step k of the stage (1, 2, ...) applies the forces times max(0, 1 - k / steps).
  double forces(Model&, double t) override;
  bool renumber(const Renumbering& r) override;

 private:
  std::vector<std::pair<int, Vec2>> forces_;
  long steps_ = 1, done_ = 0;
};

}  // namespace rockdem
