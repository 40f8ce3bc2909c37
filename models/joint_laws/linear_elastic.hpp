#pragma once
// linear_elastic: a joint that deforms and never fails. See linear_elastic.cpp.
#include "framework/plugin_api/joint_law.hpp"

namespace rockdem {

struct LinearElastic {
  static constexpr const char* name = "linear_elastic";
  struct Params {
    double kn;  // normal stiffness [Pa/m]
    double ks;  // shear stiffness [Pa/m]
    static std::vector<Param<Params>> spec();
  };
  struct State {
    double elastic_normal;  // kn x closure from the unloaded position [Pa]: negative while open
    double elastic_shear;   // ks x shear offset since the joint last closed [Pa]; 0 while open
    double sigma_n;         // [Pa] compression positive: max(0, elastic_normal)
    double tau;             // [Pa] elastic_shear
    double u_s;             // shear offset from the initial position [m]
    double u_n;             // normal displacement, opening positive [m]
    double dilation;        // always 0 (the report structure of every law)
  };
  static void init(const Params&, State& s) { s = State{}; }
  static void update(const Params& p, State& s, const JointKinematics& k, JointResponse& r, EffectChain& chain);
  static double initial_kn(const Params& p) { return p.kn; }
  static double initial_ks(const Params& p) { return p.ks; }
};

}  // namespace rockdem
