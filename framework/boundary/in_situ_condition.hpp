#pragma once
// The boundary kind "in_situ": the traction the case's in-situ stress field puts on a boundary,
// sigma(x) . n, varying with position along it, so that the far boundary of a model carries the
// field (the rock beyond the model) and the model starts in equilibrium.
#include "framework/boundary/conditions.hpp"
#include "framework/model/stress_field.hpp"

namespace rockdem {

class InSituCondition final : public BoundaryCondition {
 public:
  InSituCondition(FaceSelection sel, StressField field);
  std::string describe(const Model& m) const override;
  double forces(Model&, double t) override;

  bool renumber(const Renumbering& r) override { return rockdem::renumber(sel_, r); }

 private:
  FaceSelection sel_;
  StressField field_;
};

}  // namespace rockdem
