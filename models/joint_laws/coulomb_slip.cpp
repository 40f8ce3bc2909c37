// coulomb_slip: mohr_coulomb without its dilation parameters (see coulomb_slip.hpp).
#include "models/joint_laws/coulomb_slip.hpp"

#include <string_view>

namespace rockdem {

std::vector<Param<CoulombSlip::Params>> CoulombSlip::Params::spec() {
  std::vector<Param<Params>> out;
  for (const auto& p : MohrCoulomb::Params::spec()) {
    const std::string_view n = p.info.name;
    if (n == "dilation_angle" || n == "critical_shear_disp" || n == "dilation") continue;
    // Members of the base struct are members of this one (implicit base-to-derived conversion).
    std::visit([&](auto member) { out.push_back(Param<Params>{p.info, member}); }, p.member);
  }
  return out;
}

}  // namespace rockdem

ROCKDEM_REGISTER_JOINT_LAW(rockdem::CoulombSlip,
                           "linear elastic joint with Coulomb slip, cohesion and tensile strength (mohr_coulomb without dilation)",
                           "Cundall & Hart (1985); Itasca UDEC manual, Coulomb slip joint model")
