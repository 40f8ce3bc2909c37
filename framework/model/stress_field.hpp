#pragma once
// An in-situ stress field: the stress a rock mass carries before anything is excavated, as a
// geologist states it: the vertical stress grows with depth below a datum (the ground surface),
//   sigma_v(y) = surcharge + density * g * (surface - y),
// the horizontal stress is a fixed fraction of it, sigma_H = K sigma_v, and a constant shear
// stress may be added. Inputs are compression positive (sigma_v, sigma_H, surcharge), as in
// geomechanics; at() returns the zones' convention (tension positive, framework/model/model.hpp).
// Such a field satisfies div(sigma) + rho g = 0 for a vertical gravity g (only sigma_yy varies,
// and only with y), so a model started from it is in equilibrium.
#include "framework/core/types.hpp"

namespace rockdem {

struct StressField {
  double surface = 0.0;    // y of the datum the depth is measured from [m]
  double density = 0.0;    // density that loads the field [kg/m^3]
  double gravity = 0.0;    // magnitude of the (downward) gravity that loads it [m/s^2]
  double surcharge = 0.0;  // vertical stress at the datum, compression positive [Pa]
  double k = 1.0;          // sigma_H / sigma_v
  double sxy = 0.0;        // shear stress, tension-positive convention of the zones [Pa]

  // Vertical stress at height y, compression positive [Pa].
  double sigma_v(double y) const { return surcharge + density * gravity * (surface - y); }
  // Stress tensor (sxx, syy, sxy) at x, tension positive [Pa].
  Voigt3 at(const Vec2& x) const {
    const double sv = sigma_v(x.y());
    return {-k * sv, -sv, sxy};
  }
  // Traction sigma . n on a surface with unit normal n at x [Pa].
  Vec2 traction(const Vec2& x, const Vec2& n) const {
    const Voigt3 s = at(x);
    return {s[0] * n.x() + s[2] * n.y(), s[2] * n.x() + s[1] * n.y()};
  }
};

}  // namespace rockdem
