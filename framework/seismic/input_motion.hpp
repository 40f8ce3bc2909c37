#pragma once
// Ground motions as inputs to a dynamic model: a recorded accelerogram processed into the
// acceleration, velocity and displacement a boundary applies (docs/seismic-input.md).
//
// The chain is process_to_displacement's (window, baseline, taper, pad, zero-phase band-pass,
// integration, displacement baseline), a constant taken from the acceleration so that the
// motion ends at rest (zero final velocity), then scaling to a target peak acceleration or velocity
// (or by a factor). What the model can carry is checked separately (mesh_frequency_limit): a
// zone must be at most a tenth (by default) of the shortest shear wavelength the input carries
// (Kuhlemeyer & Lysmer 1973), and the case says whether a record above that limit is refused or
// low-pass filtered at it.
#include <string>
#include <vector>

#include "framework/seismic/ground_motion.hpp"
#include "framework/seismic/signal_processing.hpp"

namespace rockdem::seismic {

// What the record is, relative to the model's base (the choice decides the input stress at a
// compliant base; Mejia & Dawson 2006; Itasca FLAC dynamic-analysis guide):
//   outcrop:  recorded on rock outcrop: the incident (upgoing) wave is half of it;
//   incident: the upgoing wave itself (e.g. after a deconvolution);
//   within:   recorded at depth, incident plus reflected waves: only a rigid base can take it.
enum class MotionType { outcrop, incident, within };
const char* motion_type_name(MotionType t);

struct MotionScaling {
  enum class Kind { none, factor, pga, pgv } kind = Kind::none;
  double value = 1.0;  // the factor, or the target peak [m/s^2 or m/s]
  std::string describe() const;
};

// A processed motion, ready to apply: uniform samples from t = 0 (the first sample of the padded
// window) and zero afterwards.
struct InputMotion {
  std::string name;
  MotionType type = MotionType::outcrop;
  int direction = 0;  // 0: x (horizontal), 1: y (vertical)
  double dt = 0.0;
  std::vector<double> acc, vel, disp;  // m/s^2, m/s, m (already scaled)
  double scale = 1.0;                  // factor the processing applied to the record
  double f_high = 0.0;                 // upper cut-off applied [Hz], 0: none
  std::string processing;              // one line: every processing step and its values
  std::string source;                  // record file and column

  double duration() const { return acc.empty() ? 0.0 : dt * static_cast<double>(acc.size() - 1); }
  // Linear between samples, zero before 0 and after the end (the motion ends at rest).
  double velocity(double t) const { return sample(vel, t); }
  double acceleration(double t) const { return sample(acc, t); }
  double displacement(double t) const;  // holds the last value after the end
  double pga() const;
  double pgv() const;
  double pgd() const;  // peak displacement [m]
  // The factor that brings this motion to a scaling's target (1 for none).
  double factor_for(const MotionScaling& s) const;

 private:
  double sample(const std::vector<double>& x, double t) const;
};

InputMotion make_input_motion(const GroundMotion& g, const DisplacementProcessing& p, const MotionScaling& s);

// The highest frequency a mesh carries with `zones_per_wavelength` zones of size `zone_size` per
// shear wavelength at speed `cs`: cs / (zones_per_wavelength * zone_size).
double mesh_frequency_limit(double cs, double zone_size, double zones_per_wavelength);

// The frequency below which `fraction` of the signal's Fourier power lies (zero-padded FFT).
double power_frequency(std::span<const double> x, double dt, double fraction);

}  // namespace rockdem::seismic
