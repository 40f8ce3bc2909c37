#pragma once
// mohr_coulomb_rock: elastic, perfectly plastic Mohr-Coulomb rock matrix with tension cut-off and
// non-associated flow (dilation angle), plane strain.
#include <cstdint>

#include "framework/plugin_api/rock_material.hpp"

namespace rockdem {

struct MohrCoulombRock {
  static constexpr const char* name = "mohr_coulomb_rock";
  struct Params {
    double density;   // [kg/m^3]
    double bulk;      // [Pa]
    double shear;     // [Pa]
    double friction;  // [rad]
    double cohesion;  // [Pa]
    double dilation;  // [rad], <= friction
    double tension;   // tensile strength [Pa]; capped at the apex c/tan(phi)
    static std::vector<Param<Params>> spec();
    void validate() const;
  };
  // Failure flags, as FLAC reports them.
  static constexpr std::uint32_t shear_now = 1, tension_now = 2, shear_past = 4, tension_past = 8;
  struct State {
    double plastic_shear;    // accumulated plastic shear strain measure (FLAC e^ps)
    double plastic_tension;  // accumulated plastic tensile strain (FLAC e^pt)
    std::uint32_t flags;
  };
  static void update(const Params& p, State& s, const Voigt3& de, Voigt3& sigma, double& szz);
  // Effective tensile strength: min(tension, c / tan(phi)).
  static double tension_cutoff(const Params& p);
  // FLAC's shear yield function f_s = s1 - s3 N_phi + 2 c sqrt(N_phi), s1 <= s3 the extreme
  // principal stresses (tension positive); f_s < 0 is beyond the yield surface.
  static double shear_yield(const Params& p, double s1, double s3);
};

}  // namespace rockdem
