#pragma once
// Continuously-yielding joint (Cundall & Hart 1985; Cundall & Lemos 1990; CNWRA report eqs.
// 3-8..3-17). See continuously_yielding.cpp.
#include "framework/plugin_api/joint_law.hpp"

namespace rockdem {

struct ContinuouslyYielding {
  static constexpr const char* name = "continuously_yielding";
  struct Params {
    double kn, kn_min, kn_max, kn_exponent;  // kn = kn*(sigma_n/ref)^e bounded [Pa/m]
    double ks, ks_min, ks_max, ks_exponent;  // ks likewise (eq. 3-9)
    double reference_stress;                 // stress unit of the power laws [Pa]
    double initial_friction;                 // phi_m0 [rad]
    double friction;                         // basic friction phi [rad]
    double roughness;                        // R [m]
    double critical_shear_disp;              // [m]
    int dilation;                            // law_support::DilationOption
    void validate() const;
    static std::vector<Param<Params>> spec();
  };
  struct State {
    double sigma_n;       // [Pa] compression positive
    double tau;           // [Pa]
    double u_s;           // shear offset from the mated position [m]
    double u_n;           // normal displacement, opening positive [m]
    double gap;           // opening beyond the touching point while open (>0) [m]
    double plastic_slip;  // u_s^p of eq. 3-14 [m]
    double r;             // reversal factor of eq. 3-11
    double last_dir;      // sign of the last non-zero shear increment (0 before any)
    double dilation;      // accumulated shear dilation [m]
    bool ucs_reached;
  };
  static double normal_stiffness(const Params& p, double sigma_n);
  static double shear_stiffness(const Params& p, double sigma_n);
  // phi_m of eq. 3-14 for a plastic shear displacement u_p [rad].
  static double phi_m(const Params& p, double u_p);
  static void init(const Params& p, State& s);
  static void update(const Params& p, State& s, const JointKinematics& k, JointResponse& r,
                     EffectChain& chain);
  static double initial_kn(const Params& p) { return normal_stiffness(p, 0.0); }
  static double initial_ks(const Params& p) { return shear_stiffness(p, 0.0); }
  // Kept fixed by `rockdem calibrate` unless freed: the normal stiffness (a constant-normal-stress
  // record never shows the closure), the stiffness power laws' exponents, clamps and stress unit
  // (a few normal stresses cannot resolve them), and u_cs (infinite unless written).
  static std::vector<std::string> fixed_by_default() {
    return {"kn", "kn_min", "kn_max", "kn_exponent", "ks_min", "ks_max", "ks_exponent", "reference_stress",
            "critical_shear_disp"};
  }
};

}  // namespace rockdem
