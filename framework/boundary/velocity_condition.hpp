#pragma once
// The boundary kind "velocity": velocity components prescribed as functions of stage time.
#include <optional>

#include "framework/boundary/conditions.hpp"

namespace rockdem {

// Prescribed velocity components (functions of stage time) on gridpoints or a rigid block.
// Components left empty stay free.
class VelocityCondition final : public BoundaryCondition {
 public:
  VelocityCondition(FaceSelection sel, bool whole_rigid_block, std::optional<TimeFunction> vx,
                    std::optional<TimeFunction> vy, std::optional<TimeFunction> spin);
  std::string describe(const Model& m) const override;
  void setup(Model&) override;
  void velocities(Model&, double t) override;
  // Longest finite duration of its velocity histories (0 if none is finite).
  double duration() const;
  double history_duration() const override { return duration(); }

  bool renumber(const Renumbering& r) override { return rockdem::renumber(sel_, r); }

 private:
  FaceSelection sel_;
  bool rigid_;
  std::optional<TimeFunction> vx_, vy_, spin_;
};

}  // namespace rockdem
