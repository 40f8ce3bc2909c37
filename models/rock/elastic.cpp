#include "models/rock/elastic.hpp"

namespace rockdem {

std::vector<Param<ElasticRock::Params>> ElasticRock::Params::spec() {
  using P = Params;
  return {
      real("density", &P::density, Dimension::density, "mass density").positive(),
      real("bulk", &P::bulk, Dimension::stress, "bulk modulus K").positive(),
      real("shear", &P::shear, Dimension::stress, "shear modulus G").positive(),
  };
}

void ElasticRock::update(const Params& p, State& /*s*/, const Voigt3& de, Voigt3& sigma, double& szz) {
  const double a1 = p.bulk + 4.0 * p.shear / 3.0, a2 = p.bulk - 2.0 * p.shear / 3.0;
  sigma[0] += a1 * de[0] + a2 * de[1];
  sigma[1] += a2 * de[0] + a1 * de[1];
  sigma[2] += p.shear * de[2];
  szz += a2 * (de[0] + de[1]);
}

}  // namespace rockdem

ROCKDEM_REGISTER_ROCK_MATERIAL(rockdem::ElasticRock, "isotropic linear elastic rock matrix (plane strain)",
                               "Hooke's law; Itasca UDEC theory, deformable blocks")
