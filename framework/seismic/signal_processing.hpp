#pragma once
// Processing of uniformly sampled signals (accelerograms and what is derived from them):
// polynomial baseline removal, cosine tapers, zero padding, zero-phase Butterworth filtering,
// trapezoidal integration, the dominant frequency, scaling to a peak; and the chain that turns
// an accelerogram into a displacement history. Equations and sources: docs/theory/ground_motion.md.
// All functions are pure (no global state); bad arguments are InputErrors.
#include <span>
#include <string>
#include <vector>

#include "framework/seismic/ground_motion.hpp"

namespace rockdem::seismic {

// Least-squares fit of sum_{k=lowest..degree} c_k tau^k (tau = time from the first sample) and
// its removal from x. lowest = 0 is an ordinary polynomial detrend; lowest = 2 on a displacement
// keeps its zero initial value and slope (the corrected motion still starts at rest).
// Returns the polynomial that was removed.
struct PolynomialFit {
  std::vector<double> coeff;  // of (tau / duration)^(lowest + k)
  int lowest = 0;
  double duration = 1.0;  // s
  // The fit and its first two time derivatives at tau (s).
  double value(double tau) const { return eval(tau, 0); }
  double rate(double tau) const { return eval(tau, 1); }
  double rate2(double tau) const { return eval(tau, 2); }
  double eval(double tau, int derivative) const;
};
PolynomialFit remove_polynomial_baseline(std::vector<double>& x, double dt, int degree, int lowest = 0);

// Half-cosine (Hann) ramps of `length` seconds at both ends: x is scaled by
// (1 - cos(pi t / length)) / 2 over the first `length` and mirrored at the end.
void cosine_taper(std::vector<double>& x, double dt, double length);

// `before` and `after` seconds of zeros around x (rounded to whole samples).
std::vector<double> zero_pad(std::span<const double> x, double dt, double before, double after);

// One second-order (or first-order, a2 = b2 = 0) section, a0 normalised to 1.
struct Biquad {
  double b0, b1, b2, a1, a2;
};
// Digital Butterworth high-pass (f_low) and low-pass (f_high) by the bilinear transform with
// prewarped corners, as cascaded sections. f_low = 0: no high-pass; f_high = 0: no low-pass.
std::vector<Biquad> butterworth_bandpass(double dt, double f_low, double f_high, int order);
// Filter in place, forward (direct form II transposed, zero initial state).
void filter_forward(std::vector<double>& x, const std::vector<Biquad>& sections);
// Zero-phase: forward, then backward (|H|^2, no delay). Pad the signal with zeros first so the
// filter transients have room (Boore 2005).
void filter_zero_phase(std::vector<double>& x, const std::vector<Biquad>& sections);

// Cumulative trapezoid rule, y[0] = initial.
std::vector<double> integrate_trapezoid(std::span<const double> x, double dt, double initial = 0.0);

// Frequency (Hz) of the largest FFT amplitude, the zero-frequency bin excluded.
double dominant_frequency(std::span<const double> x, double dt);

double peak_abs(std::span<const double> x);
// Scale x so that max |x| = target; returns the factor. A zero signal is an InputError.
double scale_to_peak(std::vector<double>& x, double target);

// The accelerogram -> displacement chain, in this order (each step optional as noted):
// 1 window [start, end] of the record; 2 remove a polynomial of acc_baseline_degree from the
// acceleration (-1: none); 3 cosine taper of `taper` s at both ends; 4 zero pads of `pad` s at
// both ends; 5 zero-phase Butterworth band-pass (f_low, f_high, order; 0 = that side off);
// 6 trapezoidal integration to velocity and displacement from rest; 7 remove a polynomial of
// degree disp_baseline_degree with no constant and linear terms from the displacement (0: none);
// 8 scale to a peak |displacement| (0: no scaling; velocity and acceleration scale alike).
struct DisplacementProcessing {
  double start = -1.0;  // s, record time; < 0: from the first sample
  double end = -1.0;    // s; < 0: to the last sample
  int acc_baseline_degree = 1;
  double taper = 0.0;   // s
  double pad = 0.0;     // s
  double f_low = 0.0;   // Hz
  double f_high = 0.0;  // Hz
  int order = 2;
  int disp_baseline_degree = 0;
  double peak_displacement = 0.0;  // m
  // One line naming every parameter (units written), for the drive file's metadata.
  std::string describe() const;
  void validate(double dt) const;  // InputError naming the parameter and its valid range
};

struct ProcessedMotion {
  double dt = 0.0;
  std::vector<double> time;            // s, from 0 at the first sample of the (padded) window
  std::vector<double> acc, vel, disp;  // m/s^2, m/s, m
  double scale = 1.0;                  // factor applied in step 8
  double record_start = 0.0;           // record time of the first window sample (before padding)
};

ProcessedMotion process_to_displacement(const GroundMotion& g, const DisplacementProcessing& p);

}  // namespace rockdem::seismic
