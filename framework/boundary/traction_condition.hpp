#pragma once
// The boundary kind "traction": normal and shear stress on a face.
#include "framework/boundary/conditions.hpp"

namespace rockdem {

// Traction on a face: normal stress (compression positive, pushing into the block) and shear
// stress (positive along the face tangent, counter-clockwise around the block), as functions of
// time, integrated over the current edge lengths.
class TractionCondition final : public BoundaryCondition {
 public:
  TractionCondition(FaceSelection sel, TimeFunction normal, TimeFunction shear);
  std::string describe(const Model& m) const override;
  double forces(Model&, double t) override;

  bool renumber(const Renumbering& r) override { return rockdem::renumber(sel_, r); }

 private:
  FaceSelection sel_;
  TimeFunction normal_, shear_;
};

}  // namespace rockdem
