#pragma once
// Viscous (quiet) boundaries, with the seismic input of a compliant base and the static forces a
// boundary held before it became quiet: the kinds "quiet" and "seismic" (base = "compliant").
#include "framework/boundary/condition_kinds.hpp"
#include "framework/boundary/conditions.hpp"

namespace rockdem {

// Normal and shear dashpots rho*Cp and rho*Cs per unit length (Lysmer & Kuhlemeyer 1969),
// absorbing outgoing waves, on the gridpoints of a deformable block's face or on a rigid block
// (whose gridpoints move with it, so the dashpot forces become a force and a moment on it).
//
// Seismic input (compliant base): the stage's motions enter as the stress 2 rho C v_in of the
// incident wave v_in (FLAC/UDEC's stress input; Mejia & Dawson 2006), split into the face's normal
// (Cp) and tangential (Cs) parts; an outcrop record is twice the incident wave, so it enters as
// rho C v_outcrop.
//
// Static hand-over: a boundary held fixed in a static stage carries reactions. When it becomes
// quiet, dashpots alone cannot hold them (they resist velocity, not load), and the model would
// creep. At the start of the first stage in which the condition is active it takes the forces the
// previous stage left unbalanced on its gridpoints (the reactions of the fixed degrees of freedom;
// for a rigid block its net force and moment) and applies their opposite as constant forces from
// then on, so the in-situ stress stays in equilibrium.
class QuietCondition final : public BoundaryCondition {
 public:
  struct Options {
    bool seismic_input = false;  // the compliant base of kind "seismic"
    bool hold_static = true;     // static_reactions = "hold"
    bool rigid = false;          // the selection is a whole rigid block's face
  };
  QuietCondition(FaceSelection sel, double rho, double cp, double cs, Options o);
  std::string describe(const Model& m) const override;
  void setup(Model& m) override;
  void deactivated() override;
  double forces(Model&, double t) override;
  // A within record (incident plus reflected waves) at a compliant base is an InputError.
  void set_motions(const std::vector<StageMotion>& motions) override;
  bool takes_motions() const override { return o_.seismic_input; }
  double history_duration() const override;
  void add_dashpots(const Model& m, std::vector<double>& c) const override;
  std::vector<double> saved_state() const override;
  void restore_state(const std::vector<double>& s) override;
  bool renumber(const Renumbering& r) override { return rockdem::renumber(sel_, r); }

 private:
  FaceSelection sel_;
  double rho_, cp_, cs_;
  Options o_;
  std::vector<StageMotion> motions_;
  bool held_ = false;            // the static forces were taken (at the first active stage)
  std::vector<Vec2> hold_;       // deformable: per selected gridpoint [N/m]
  Vec2 hold_force_ = Vec2::Zero();  // rigid: net force and moment about the centroid
  double hold_moment_ = 0.0;
};

// Forces adding up to `force` and to `moment` about the block's centroid, spread over the rigid
// block's gridpoints (a uniform share plus a rotation-like field about their mean position), so
// that a load held on a rigid block needs no point of application of its own.
void add_rigid_load(Model& m, int block, const Vec2& force, double moment);

// Density and wave speeds of the material behind a face: the first zone of a deformable block,
// or (rigid blocks, which carry no elastic constants) the `rho`, `cp`, `cs` values of the
// condition; throws an InputError at `where` naming them when a rigid block's are missing.
struct WaveImpedance {
  double rho = 0.0, cp = 0.0, cs = 0.0;
};
WaveImpedance face_impedance(const ConditionInput& in);

// What the stage's motions put in at a base at stage time t, by component: for a compliant base
// twice the incident wave (an outcrop record already is; an incident one is doubled), for a rigid
// base the motion itself. And how long the longest of them lasts.
Vec2 base_input(const std::vector<BoundaryCondition::StageMotion>& motions, double t, bool rigid_base);
double motions_duration(const std::vector<BoundaryCondition::StageMotion>& motions);

// The keys of the kinds that put dashpots on a face (quiet, seismic, free_field): cp, cs,
// density, static_reactions; and the static_reactions choice read from them.
std::vector<ConditionKey> dashpot_keys();
bool hold_static_reactions(const ConditionInput& in);

}  // namespace rockdem
