#pragma once
// The boundary kind "quiet": a viscous boundary absorbing outgoing waves.
#include "framework/boundary/conditions.hpp"

namespace rockdem {

// Viscous (quiet) boundary: normal and shear dashpots rho*Cp and rho*Cs per unit length
// (Lysmer & Kuhlemeyer 1969), absorbing outgoing waves.
class QuietCondition final : public BoundaryCondition {
 public:
  QuietCondition(FaceSelection sel, double rho, double cp, double cs);
  std::string describe(const Model& m) const override;
  double forces(Model&, double t) override;

  bool renumber(const Renumbering& r) override { return rockdem::renumber(sel_, r); }

 private:
  FaceSelection sel_;
  double rho_, cp_, cs_;
};

}  // namespace rockdem
