#pragma once
// The virtual lab's direct-shear box: a physically based single-joint model, independent of the
// joint laws in models/joint_laws/ and of every effect module, that makes synthetic measurement
// twins of laboratory direct-shear tests. See docs/virtual-lab.md for the equations.
//
// Two matched rough surfaces (heights on one grid): the bottom one fixed, the top one (a rigid
// block, shorter than the bottom one as in the laboratory specimen) offset horizontally by s and
// lifted by v. Where the offset surfaces overlap by delta > 0, an elastic asperity foundation
// (a contact stiffness k_c per unit length) carries the vertical force
//     V_i = min(k_c delta_i, p_crush) dx,
// capped at the wall strength p_crush, beyond which the asperity crushes (the excess overlap is
// removed from both surfaces). v solves the normal equilibrium sum V_i = sigma_n L each state.
// Each contacting facet (inclination theta_i) carries a Coulomb contact force inclined by the
// friction angle phi to its normal, so the horizontal resistance is (Patton 1966, per facet)
//     H_i = V_i tan(theta_i + phi sign(slip)),   tau = sum H_i / L.
// Wear (Archard 1953, in its frictional-work form): each sliding increment removes from BOTH
// surfaces, at the contact where the work is done, a volume k_w W_f / p_crush, W_f the
// frictional work on the facet. Optional regularised rate-and-state friction on the facets
// (Dieterich 1979 ageing law, Ruina 1983; regularised as Rice & Ben-Zion 1996) with an
// inertial top block driven through a compliant frame.
//
// The shear chain is: drive u_d --(frame spring k_f)-- top block --(asperity shear spring k_s)--
// geometric offset s. Quasi-static mode: s is where the Coulomb bounds are met (stick or slide,
// with a jump where the resistance falls faster than the chain stiffness: quasi-static slip).
// Inertial mode: the block (mass per unit area m) moves by Newton's law, implicit in velocity.
// The recorded shear displacement is s + tau/k_s (what an LVDT across the joint sees), the
// recorded shear stress is the chain force (the load cell), the normal displacement is v.
//
// No global mutable state; no MPI. One ShearBox is one specimen.
#include <cstdint>
#include <vector>

#include "framework/io/measurement_csv.hpp"
#include "framework/lab/element_driver.hpp"
#include "framework/lab/virtual_lab/rough_profile.hpp"

namespace rockdem::vlab {

struct BoxParams {
  double friction = 0.5;              // basic friction angle phi_b of the facets [rad]
  double contact_stiffness = 2e12;    // k_c, asperity normal stiffness per unit length [Pa/m]
  double shear_stiffness = 10e9;      // k_s, elastic shear stiffness of the asperities [Pa/m]
  double wall_strength = 120e6;       // p_crush: crushing pressure and Archard hardness [Pa]
  double wear_coefficient = 0.0;      // k_w, dimensionless (volume k_w W_f / p_crush)
  double max_angle = 1.3;             // cap on |theta + phi| of a facet [rad] (shear-through)
  // Inertial mode and loading frame.
  bool inertial = false;
  double frame_stiffness = 0.0;       // k_f per unit joint area [Pa/m]; 0 = rigid frame
  double moving_mass = 247.0;         // mass of the moving block per unit joint area [kg/m^2]
  double time_step = 5e-5;            // inertial time step [s]
  // Rate and state (inertial mode only).
  bool rate_state = false;
  double rs_a = 0.01, rs_b = 0.015;   // direct and evolution effects
  double rs_dc = 10e-6;               // characteristic slip distance [m]
  double rs_v0 = 1e-6;                // reference velocity, at which mu_ss = tan(friction) [m/s]
  // Quasi-static drive.
  double step = 0.02e-3;              // largest drive increment [m]
  // Output.
  double output_interval = 1.0;       // time between recorded rows [s]
  double noise_stress = 0.0;          // standard deviations of the measurement noise [Pa]
  double noise_shear_disp = 0.0;      // [m]
  double noise_normal_disp = 0.0;     // [m]
};

// Heights of the two surfaces on one grid: bottom node j at bottom_x0 + j grid, top node i at
// top_x0 + i grid in the top block's own frame (x at zero offset).
struct Surfaces {
  double grid = 0.0;
  double bottom_x0 = 0.0;
  std::vector<double> bottom;
  double top_x0 = 0.0;
  std::vector<double> top;
};

// Matched surfaces: the bottom is `heights` (centred on x = 0), the top is a copy of its middle
// `top_length`.
Surfaces matched_surfaces(const std::vector<double>& heights, double grid, double top_length);
// The same with the top cut from the middle of another wall (`upper`, same grid and length).
Surfaces matched_surfaces(const std::vector<double>& lower, const std::vector<double>& upper, double grid,
                          double top_length);

// What the contact carries at one offset under the current normal stress.
struct Resistance {
  double lift = 0.0;        // v [m]
  double tau_forward = 0.0; // shear stress to slide in +x [Pa]
  double tau_backward = 0.0;// shear stress to slide in -x (negative when resisting) [Pa]
  double contact_fraction = 0.0;
};

class ShearBox {
 public:
  ShearBox(Surfaces surfaces, BoxParams params, std::uint64_t noise_seed = 0);
  // (noise_seed seeds the measurement noise; the surfaces carry the profile's own seed.)

  // Runs the stages in sequence on this specimen (wear carried over) and appends rows (extra
  // columns drive_disp_mm, contact_fraction). Stages under constant normal stiffness are refused.
  void run(const std::vector<ElementStage>& stages, MeasurementFile& out, int first_stage_number = 1);

  // Lower level, for tests: apply a normal stress at the present offset, and the resistance at an
  // offset s under it (no state change except the cached lift used as the next starting guess).
  void set_normal_stress(double sigma_n);
  Resistance resistance(double s);

  const Surfaces& surfaces() const { return surf_; }
  double offset() const { return s_; }
  long evaluations() const { return evaluations_; }
  long steps() const { return steps_; }
  double worn_volume() const { return worn_volume_; }  // per unit width, both surfaces [m^2]

 private:
  struct Contact {
    std::size_t node;  // top node
    double vertical;   // V_i [N/m]
    double theta;      // facet inclination [rad]
    double tan_theta;
    double overlap;    // delta_i [m]
  };
  // Fills contacts_ for offset s and solves the normal equilibrium (lift_).
  void evaluate(double s);
  // Horizontal resistance [Pa] of the present contacts for a signed friction coefficient, and
  // optionally its derivative with respect to that coefficient.
  double horizontal(double mu_signed, double* d_dmu = nullptr) const;
  double mu_rate_state(double velocity, double* dmu_dv) const;
  // Accepted slip ds at the present contacts: wear and crushing change both surfaces.
  void wear(double ds, double mu_signed);
  void remove(std::size_t top_node, double depth_top, double depth_bottom);
  void crush();
  double bottom_height(double x, std::size_t* j, double* w) const;
  double bottom_slope(double x) const;
  double top_slope(std::size_t i) const;
  double chain_stiffness() const;

  void quasi_static_step(double u_drive);
  void inertial_step(double u_drive, double dt);

  Surfaces surf_;
  BoxParams p_;
  double length_;       // top length [m]
  double sigma_ = 0.0;  // normal stress [Pa]
  double s_ = 0.0;      // geometric offset [m]
  double vel_ = 0.0;    // slip velocity [m/s]
  double tau_ = 0.0;    // chain force per unit area [Pa]
  double lift_ = 0.0;   // v [m]
  double rs_state_;     // rate-and-state theta [s]
  std::vector<double> h_;  // bottom minus top height per top node at the evaluated offset
  std::vector<Contact> contacts_;
  SeededRandom noise_;
  long evaluations_ = 0, steps_ = 0;
  double worn_volume_ = 0.0;
};

}  // namespace rockdem::vlab
