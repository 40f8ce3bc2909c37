#pragma once
// Physical quantities in case files are written with their unit ("16.93 GPa/m", "38 deg",
// "100 mm/s"); inside rockdem everything is SI (angles in radians). A dimensional value without
// a unit is an error: it is the commonest silent mistake in geomechanics inputs.
#include <string>
#include <string_view>

namespace rockdem {

enum class Dimension {
  dimensionless,
  length,          // m
  stress,          // Pa
  stiffness,       // Pa/m (joint stiffness: stress per unit displacement)
  angle,           // rad (written in deg or rad)
  time,            // s
  velocity,        // m/s
  acceleration,    // m/s^2
  density,         // kg/m^3
  frequency,       // Hz (cycles per second)
  angular_velocity,// rad/s (spin)
  energy_per_area, // J/m^2
  force,           // N
  mass_per_area,   // kg/m^2 (block mass per unit joint area)
};

std::string_view dimension_name(Dimension d);
// Units a user may write for a dimension, for error messages ("MPa, GPa, kPa, Pa").
std::string_view units_for(Dimension d);
// SI unit used when printing values of this dimension.
std::string_view si_unit(Dimension d);

// Parse "<number> <unit>" into SI. Throws InputError (message without location: the caller adds
// the file and key) when the unit is unknown, missing, or of another dimension.
double parse_quantity(std::string_view text, Dimension want);

// Convert an SI value back into the unit a user most likely wrote, for display ("38 deg").
std::string format_quantity(double value_si, Dimension d);

// The shortest text that reads back as exactly `v` (std::to_chars), for files and metadata.
std::string round_trip_text(double v);

}  // namespace rockdem
