#pragma once
// Starting a model from an in-situ stress field (framework/model/stress_field.hpp): zones take
// the field's stress at their centroid and contacts the traction the field puts on them, so that
// the model is in equilibrium at step 0 without moving.
#include "framework/contact/detection.hpp"
#include "framework/model/model.hpp"
#include "framework/model/stress_field.hpp"

namespace rockdem {

struct InSituReport {
  int zones = 0;             // zones given the field's stress
  int contacts = 0;          // contacts pre-loaded
  int at_strength = 0;       // contacts whose shear target exceeds the joint's strength (they slip)
  double worst_error = 0.0;  // largest |stress reached - target| over the pre-loaded contacts [Pa]
};

// Zones: stress = the field at the zone's centroid, szz = nu (sxx + syy) (plane strain, elastic
// from the material's K and G). Contacts: detects them, then drives each touching contact's
// joint-law state (base law and effects, through JointModel::update) with normal and then shear
// increments until its stresses equal the field's traction at the contact point, normal
// sigma_n = -n.sigma.n and shear tau = t.sigma.n (t = (n_y, -n_x), the engine's shear
// direction). This pre-loads the law's state only: the blocks do not move. Works for any law
// whose normal stress grows with closure and shear stress with shear displacement, nonlinear ones
// included (the increments are found by bracketing and bisection, not from a stiffness).
// Drives one contact's joint-law state (as above; `state`, model.state_size() bytes) to the
// normal stress `sigma_n` (compression positive) and shear stress `tau`; returns the remaining
// error [Pa]. `at_strength`: the shear target is beyond the joint's strength, the state is left
// at the onset of slip.
double preload_contact(Contact& c, std::byte* state, const JointModel& model, double sigma_n, double tau,
                       bool& at_strength);

InSituReport initialise_in_situ(Model& m, const StressField& field, const DetectionSettings& detection);

}  // namespace rockdem
