#pragma once
// elastic: isotropic linear elastic rock matrix, plane strain.
#include "framework/plugin_api/rock_material.hpp"

namespace rockdem {

struct ElasticRock {
  static constexpr const char* name = "elastic";
  struct Params {
    double density;  // [kg/m^3]
    double bulk;     // bulk modulus K [Pa]
    double shear;    // shear modulus G [Pa]
    static std::vector<Param<Params>> spec();
  };
  struct State {};  // no history
  // Hooke's law in increments: dsigma = D de, with dszz = (K - 2G/3)(dexx + deyy) (plane strain).
  static void update(const Params& p, State& s, const Voigt3& de, Voigt3& sigma, double& szz);
};

}  // namespace rockdem
