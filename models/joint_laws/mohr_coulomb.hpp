#pragma once
// Mohr-Coulomb joint with UDEC-style dilation (CNWRA report eqs. 3-1..3-4). See mohr_coulomb.cpp.
#include "framework/plugin_api/joint_law.hpp"

namespace rockdem {

struct MohrCoulomb {
  static constexpr const char* name = "mohr_coulomb";
  struct Params {
    double kn;                   // normal stiffness [Pa/m]
    double ks;                   // shear stiffness [Pa/m]
    double friction;             // friction angle phi [rad]
    double cohesion;             // C [Pa]
    double tension;              // tensile strength [Pa]
    double dilation_angle;       // psi [rad]
    double critical_shear_disp;  // u_cs [m] (inf: never reached)
    int dilation;                // law_support::DilationOption
    bool residual_after_failure;
    static std::vector<Param<Params>> spec();
  };
  // tan(phi) and tan(psi), made once per parameter set instead of on every update.
  struct Derived {
    double tan_friction, tan_dilation;
  };
  static Derived derive(const Params& p);
  struct State {
    double sigma_n;       // [Pa] compression positive
    double tau;           // [Pa]
    double u_s;           // shear offset from the mated position [m]
    double u_n;           // normal displacement, opening positive [m]
    double gap;           // opening beyond the touching point while open (>0) [m]
    double plastic_slip;  // accumulated |plastic shear displacement| [m]
    double dilation;      // accumulated shear dilation [m]
    double cohesion;      // current cohesion [Pa]
    double tension;       // current tensile strength [Pa]
    bool ucs_reached;     // udec_legacy: u_cs has been reached at least once
  };
  static void init(const Params& p, State& s);
  static void update(const Params& p, const Derived& d, State& s, const JointKinematics& k, JointResponse& r,
                     EffectChain& chain);
  static double initial_kn(const Params& p) { return p.kn; }
  static double initial_ks(const Params& p) { return p.ks; }
  // Kept fixed by `rockdem calibrate` unless freed: a shear record at constant normal stress
  // measures the normal displacement from each stage's start, so kn never shows; cohesion and
  // tensile strength trade off with the friction angle over a few normal stresses; u_cs is
  // infinite unless written.
  static std::vector<std::string> fixed_by_default() { return {"kn", "cohesion", "tension", "critical_shear_disp"}; }
};

}  // namespace rockdem
