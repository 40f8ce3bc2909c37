// hyperbolic_normal_closure: the nonlinear normal closure of Bandis, Lumsden & Barton (1983) for
// any base law. Measured closure curves of rock joints are hyperbolae,
//   sigma_n = Kni V / (1 - V/Vm),      tangent kn = Kni / (1 - V/Vm)^2,
// stiff near the maximum closure Vm and soft (Kni) when the joint is barely touching. The effect
// replaces the base law's normal stress-closure relation (linear kn for Mohr-Coulomb, the power
// law of Continuously-Yielding, linear or the same hyperbola for Barton-Bandis) through the
// normal-response hook: the law keeps its shear rules and applies its increments of closure
// (opening, dilation under constrained normal displacement) on this curve. A tensile stress
// (Mohr-Coulomb's tensile strength) uses the initial stiffness Kni. Shear strength is untouched.
#include <algorithm>
#include <cmath>

#include "framework/plugin_api/effect.hpp"
#include "framework/plugin_api/law_support.hpp"

namespace rockdem {

struct HyperbolicNormalClosure {
  static constexpr const char* name = "hyperbolic_normal_closure";
  struct Params {
    bool enabled;
    double kni;  // [Pa/m]
    double vm;   // [m]
    static std::vector<Param<Params>> spec() {
      return {
          flag("enabled", &Params::enabled, true, "apply the effect; false leaves the base law unchanged, bit for bit"),
          real("initial_normal_stiffness", &Params::kni, Dimension::stiffness,
               "Kni: normal stiffness of the barely touching joint (Bandis et al. 1983: from JRC, JCS and the "
               "aperture, e.g. 10-40 GPa/m for fresh tuff joints)")
              .positive()
              .def(20e9),
          real("max_closure", &Params::vm, Dimension::length,
               "Vm: maximum closure, the asymptote of the hyperbola (Bandis et al. 1983; a few hundredths of a "
               "millimetre to a few tenths)")
              .positive()
              .def(5e-5),
      };
    }
  };
  struct State {};  // the curve is elastic: closure is a function of the normal stress
  static void init(const Params&, State&) {}
  static std::string unjudgeable(const RecordFeatures& f) {
    bool varies = false;
    for (const auto& s : f.stages) {
      const double spread = s.max_normal_stress_MPa - s.min_normal_stress_MPa;
      varies = varies || spread > 0.1 * std::max(std::abs(s.normal_stress_MPa), 1e-3);
    }
    if (!varies) {
      return "the normal stress is constant within each stage and the normal displacement is measured from each "
             "stage's start, so the closure curve never shows";
    }
    return {};
  }
  static void modify(const Params&, State&, ShearContext&) {}
  static void after(const Params&, State&, const ShearContext&, const JointResponse&) {}
  static double normal_stress(const Params& p, double v) {
    return v >= 0.0 ? law_support::BandisHyperbola{p.kni, p.vm}.sigma(v) : p.kni * v;
  }
  static double normal_closure(const Params& p, double sigma_n) {
    return sigma_n >= 0.0 ? law_support::BandisHyperbola{p.kni, p.vm}.closure(sigma_n) : sigma_n / p.kni;
  }
  static double normal_tangent(const Params& p, double v) {
    return v >= 0.0 ? law_support::BandisHyperbola{p.kni, p.vm}.tangent(v) : p.kni;
  }
};

}  // namespace rockdem

ROCKDEM_REGISTER_EFFECT(rockdem::HyperbolicNormalClosure,
                        "Bandis hyperbolic normal closure sigma_n = Kni V/(1 - V/Vm) for any base law",
                        "Bandis, Lumsden & Barton (1983) IJRMMS 20(6):249-268; Barton, Bandis & Bakhtar (1985)")
