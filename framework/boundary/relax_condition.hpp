#pragma once
// The forces removed blocks exerted on the blocks that remain, applied after an excavation and
// reduced linearly to zero over a number of steps (the "relax" of UDEC and FLAC), so that an
// opening is not made in one shock. Made by an excavation stage, not named in case files.
#include <memory>
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
  // Its progress for a checkpoint written within its stage (steps, steps done, then gridpoint and
  // force per gridpoint), and the condition made again from it; not saved_state(), which travels
  // from stage to stage by a condition's position in the case, where this one has none.
  std::vector<double> progress() const;
  // InputError when `p` is not what progress() wrote for a model of `gridpoints` gridpoints.
  static std::unique_ptr<RelaxCondition> from_progress(const std::vector<double>& p, std::size_t gridpoints);

 private:
  std::vector<std::pair<int, Vec2>> forces_;
  long steps_ = 1, done_ = 0;
};

}  // namespace rockdem
