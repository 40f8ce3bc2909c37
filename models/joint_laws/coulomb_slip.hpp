#pragma once
#include "models/joint_laws/joint_law.hpp"

namespace rockdem {

struct CoulombSlip {
  static constexpr const char* name = "coulomb_slip";
  struct Params {
    double kn;        // [Pa/m]
    double ks;        // [Pa/m]
    double friction;  // [rad]
    double cohesion;  // [Pa]
    double tension;   // [Pa]
    bool residual_after_failure;
    static std::vector<Param<Params>> spec();
  };
  struct State {
    double sigma_n;       // [Pa] compression positive
    double tau;           // [Pa]
    double u_s;           // shear offset from the mated position [m]
    double u_n;           // normal displacement, opening positive [m]
    double gap;           // opening beyond the touching point while open (>0) [m]
    double plastic_slip;  // accumulated |plastic shear| [m]
    double dilation;      // accumulated dilation from effects [m]
    double cohesion;      // current cohesion (drops to zero on failure) [Pa]
    double tension;       // current tensile strength [Pa]
  };
  static void init(const Params& p, State& s);
  static void update(const Params& p, State& s, const JointKinematics& k, JointResponse& r,
                     EffectChain& chain);
  static double initial_kn(const Params& p) { return p.kn; }
  static double initial_ks(const Params& p) { return p.ks; }
};

}  // namespace rockdem
