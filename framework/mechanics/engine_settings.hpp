#pragma once
// The settings of an Engine and of its damping, apart from the engine itself, so that case
// readers and stage descriptions can hold them without seeing the time-stepping code.
#include "framework/contact/detection.hpp"

namespace rockdem {

struct Damping {
  enum class Kind { none, local, rayleigh } kind = Kind::local;
  double local_alpha = 0.8;  // Cundall's local non-viscous damping coefficient
  double alpha = 0.0;        // Rayleigh mass-proportional coefficient [1/s]
  double beta = 0.0;         // Rayleigh stiffness-proportional coefficient [s]
  // Rayleigh coefficients for a critical-damping fraction `xi` at frequency `f` [Hz], split
  // evenly between mass and stiffness terms (minimum of the Rayleigh curve at f).
  static Damping rayleigh(double xi, double f);
  // Rayleigh coefficients giving the fraction `xi` at both f1 and f2 [Hz] (less between them):
  // alpha = 2 xi w1 w2 / (w1 + w2), beta = 2 xi / (w1 + w2) (Chopra 2012, sec. 11.4).
  static Damping rayleigh_band(double xi, double f1, double f2);
  // One term alone, with the fraction `xi` exactly at `f`: mass-proportional alpha = 2 xi w (more
  // damping below f, less above), stiffness-proportional beta = 2 xi / w (the reverse).
  static Damping rayleigh_mass(double xi, double f);
  static Damping rayleigh_stiffness(double xi, double f);
};

struct EngineSettings {
  double dt_safety = 0.5;       // fraction of the critical time step 2 sqrt(m/k)
  double fixed_dt = 0.0;        // >0: use this time step (refused at a stage start if above the stable one)
  double mass_scaling_dt = 0.0; // >0: scale inertial masses so this time step is stable
  int refresh_interval = 10;    // steps between contact detections
  DetectionSettings detection;
  double velocity_limit = 1e3;  // |v| above this is taken as a runaway [m/s]
  // Threads of this process for the zone, contact-law, contact-geometry and detection loops
  // (core/threads.hpp): the same results on any number. Not a case setting: `rockdem run --threads`.
  int threads = 1;
  // A domain-decomposed run partitions its blocks again when the load imbalance (the largest
  // process's work over the mean) exceeds this; 0: never (blocks that moved among another
  // process's blocks still go to it). Not a case setting: `rockdem run --imbalance-limit`.
  double imbalance_limit = 1.2;
};

}  // namespace rockdem
