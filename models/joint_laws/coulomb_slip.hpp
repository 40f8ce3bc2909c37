#pragma once
#include <limits>

#include "models/joint_laws/mohr_coulomb.hpp"

namespace rockdem {

// coulomb_slip: the Mohr-Coulomb joint without dilation (Cundall & Hart 1985; the UDEC Coulomb
// slip joint): linear elastic, tau <= c + sigma_n tan(phi), tensile strength, residual cohesion and
// tension after failure. It is the same law as mohr_coulomb with psi = 0, so it runs the same code:
// only its parameter list is shorter.
struct CoulombSlip {
  static constexpr const char* name = "coulomb_slip";
  struct Params : MohrCoulomb::Params {
    Params() {
      dilation_angle = 0.0;
      critical_shear_disp = std::numeric_limits<double>::infinity();
      dilation = 0;
    }
    static std::vector<Param<Params>> spec();
  };
  using State = MohrCoulomb::State;
  using Derived = MohrCoulomb::Derived;
  static Derived derive(const Params& p) { return MohrCoulomb::derive(p); }
  static void init(const Params& p, State& s) { MohrCoulomb::init(p, s); }
  static void update(const Params& p, const Derived& d, State& s, const JointKinematics& k, JointResponse& r,
                     EffectChain& chain) {
    MohrCoulomb::update(p, d, s, k, r, chain);
  }
  static double initial_kn(const Params& p) { return p.kn; }
  static double initial_ks(const Params& p) { return p.ks; }
  // As mohr_coulomb's (which has u_cs besides).
  static std::vector<std::string> fixed_by_default() { return {"kn", "cohesion", "tension"}; }
};

}  // namespace rockdem
