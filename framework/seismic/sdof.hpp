#pragma once
// Linear single-degree-of-freedom oscillator under base acceleration, integrated by the exact
// recurrence for a load that varies linearly within each time step (Nigam & Jennings 1969;
// Chopra, Dynamics of Structures, section 5.2). Exact for piecewise-linear excitation at any
// time step, hence the reference method for response spectra of sampled accelerograms.
#include <span>
#include <vector>

namespace rockdem::seismic {

struct SdofOscillator {
  double period = 1.0;    // s, natural period Tn
  double damping = 0.05;  // fraction of critical, 0 <= zeta < 1
};

struct SdofResponse {
  std::vector<double> u;  // m, displacement relative to the base
  std::vector<double> v;  // m/s, relative velocity
};

// Relative response to base acceleration ag (m/s^2, sampled every dt), starting from (u0, v0).
// The equation is u'' + 2 zeta wn u' + wn^2 u = -ag(t). InputError for invalid arguments.
SdofResponse sdof_response(std::span<const double> ag, double dt, const SdofOscillator& osc, double u0 = 0.0,
                           double v0 = 0.0);

// max |u| over the record, from rest.
double sdof_peak_displacement(std::span<const double> ag, double dt, const SdofOscillator& osc);

}  // namespace rockdem::seismic
