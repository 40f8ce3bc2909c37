#pragma once
// Barton-Bandis joint (CNWRA report eqs. 3-5..3-7, Barton et al. 1985). See barton_bandis.cpp.
#include "framework/plugin_api/joint_law.hpp"

namespace rockdem {

struct BartonBandis {
  static constexpr const char* name = "barton_bandis";
  // Values derived from Params (scale corrections, eq. 3-6, Bandis closure constants).
  struct Derived {
    double jrc_n, jcs_n, delta_p, kni, vm;
  };
  struct Params {
    double kn;                   // linear normal stiffness [Pa/m]
    double ks;                   // shear stiffness for unloading/reloading [Pa/m]
    double jrc;                  // JRC0, laboratory scale
    double jcs;                  // JCS0, laboratory scale [Pa]
    double residual_friction;    // phi_r [rad]
    double ucs;                  // intact uniaxial compressive strength sigma_c [Pa] (0: not given)
    double lab_length;           // L0 [m]
    double field_length;         // Ln [m] (0: same as L0)
    double critical_shear_disp;  // u_cs for udec_legacy/monotonic dilation [m]
    int dilation;                // law_support::DilationOption
    int normal_closure;          // 0 linear, 1 bandis hyperbolic
    double initial_normal_stiffness;  // Kni for the hyperbola [Pa/m] (0: Bandis et al. 1983)
    double max_closure;               // Vm [m] (0: Bandis et al. 1983)
    void validate() const;
    static std::vector<Param<Params>> spec();
  };
  struct State {
    double sigma_n;       // [Pa] compression positive
    double tau;           // [Pa]
    double u_s;           // shear offset from the mated position [m]
    double u_n;           // normal displacement, opening positive [m]
    double closure;       // elastic closure of the contact (<0: open, gap) [m]
    double delta;         // shear displacement travelled on the strength curve (JRC mobilisation) [m]
    double plastic_slip;  // accumulated |plastic shear displacement| [m]
    double dilation;      // accumulated shear dilation [m]
    bool ucs_reached;
  };
  static Derived derive(const Params& p);
  // Mobilised roughness angle JRC_mob*log10(JCS/sigma_n) [rad] at travel delta (Barton's table).
  static double mobilised_roughness(const Params& p, const Derived& d, double delta, double sigma_n);
  // Shear strength sigma_n*tan(phi_r + JRC_mob log10(JCS/sigma_n)) (eq. 3-5 with JRC_mob) [Pa].
  static double strength(const Params& p, const Derived& d, double delta, double sigma_n);
  static void init(const Params& p, State& s);
  static void update(const Params& p, const Derived& d, State& s, const JointKinematics& k, JointResponse& r,
                     EffectChain& chain);
  static double initial_kn(const Params& p);
  static double initial_ks(const Params& p) { return p.ks; }
  // Kept fixed by `rockdem calibrate` unless freed: the normal stiffness and the Bandis closure
  // constants (a constant-normal-stress record never shows the closure), JCS and UCS (index
  // properties measured on their own; JCS trades off with JRC), the specimen lengths, and u_cs
  // (infinite unless written).
  static std::vector<std::string> fixed_by_default() {
    return {"kn", "jcs", "ucs", "lab_length", "field_length", "critical_shear_disp", "initial_normal_stiffness",
            "max_closure"};
  }
};

}  // namespace rockdem
