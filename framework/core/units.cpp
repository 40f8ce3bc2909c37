#include "framework/core/units.hpp"

#include <array>
#include <charconv>
#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>

#include "framework/core/error.hpp"

namespace rockdem {
namespace {

struct UnitDef {
  std::string_view symbol;
  Dimension dim;
  double to_si;
};

constexpr double kDeg = std::numbers::pi / 180.0;

constexpr std::array kUnits{
    UnitDef{"m", Dimension::length, 1.0},          UnitDef{"mm", Dimension::length, 1e-3},
    UnitDef{"cm", Dimension::length, 1e-2},        UnitDef{"km", Dimension::length, 1e3},
    UnitDef{"um", Dimension::length, 1e-6},        UnitDef{"Pa", Dimension::stress, 1.0},
    UnitDef{"kPa", Dimension::stress, 1e3},        UnitDef{"MPa", Dimension::stress, 1e6},
    UnitDef{"GPa", Dimension::stress, 1e9},        UnitDef{"Pa/m", Dimension::stiffness, 1.0},
    UnitDef{"kPa/m", Dimension::stiffness, 1e3},   UnitDef{"MPa/m", Dimension::stiffness, 1e6},
    UnitDef{"GPa/m", Dimension::stiffness, 1e9},   UnitDef{"MPa/mm", Dimension::stiffness, 1e9},
    UnitDef{"deg", Dimension::angle, kDeg},        UnitDef{"rad", Dimension::angle, 1.0},
    UnitDef{"s", Dimension::time, 1.0},            UnitDef{"ms", Dimension::time, 1e-3},
    UnitDef{"min", Dimension::time, 60.0},         UnitDef{"h", Dimension::time, 3600.0},
    UnitDef{"m/s", Dimension::velocity, 1.0},      UnitDef{"mm/s", Dimension::velocity, 1e-3},
    UnitDef{"mm/min", Dimension::velocity, 1e-3 / 60.0},
    UnitDef{"m/s2", Dimension::acceleration, 1.0}, UnitDef{"m/s^2", Dimension::acceleration, 1.0},
    UnitDef{"g", Dimension::acceleration, 9.80665},
    UnitDef{"kg/m3", Dimension::density, 1.0},     UnitDef{"kg/m^3", Dimension::density, 1.0},
    UnitDef{"g/cm3", Dimension::density, 1000.0},  UnitDef{"Hz", Dimension::frequency, 1.0},
    UnitDef{"rad/s", Dimension::angular_velocity, 1.0}, UnitDef{"deg/s", Dimension::angular_velocity, kDeg},
    UnitDef{"J/m2", Dimension::energy_per_area, 1.0},
    UnitDef{"J/m^2", Dimension::energy_per_area, 1.0},
    UnitDef{"N", Dimension::force, 1.0},           UnitDef{"kN", Dimension::force, 1e3},
    UnitDef{"MN", Dimension::force, 1e6},
    UnitDef{"kg/m2", Dimension::mass_per_area, 1.0}, UnitDef{"kg/m^2", Dimension::mass_per_area, 1.0},
    UnitDef{"t/m2", Dimension::mass_per_area, 1e3}, UnitDef{"t/m^2", Dimension::mass_per_area, 1e3},
};

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  return s;
}

}  // namespace

std::string_view dimension_name(Dimension d) {
  switch (d) {
    case Dimension::dimensionless: return "dimensionless";
    case Dimension::length: return "length";
    case Dimension::stress: return "stress";
    case Dimension::stiffness: return "joint stiffness";
    case Dimension::angle: return "angle";
    case Dimension::time: return "time";
    case Dimension::velocity: return "velocity";
    case Dimension::acceleration: return "acceleration";
    case Dimension::density: return "density";
    case Dimension::frequency: return "frequency";
    case Dimension::angular_velocity: return "angular velocity";
    case Dimension::energy_per_area: return "energy per area";
    case Dimension::force: return "force";
    case Dimension::mass_per_area: return "mass per area";
  }
  return "?";
}

std::string_view si_unit(Dimension d) {
  switch (d) {
    case Dimension::dimensionless: return "";
    case Dimension::length: return "m";
    case Dimension::stress: return "Pa";
    case Dimension::stiffness: return "Pa/m";
    case Dimension::angle: return "rad";
    case Dimension::time: return "s";
    case Dimension::velocity: return "m/s";
    case Dimension::acceleration: return "m/s^2";
    case Dimension::density: return "kg/m^3";
    case Dimension::frequency: return "Hz";
    case Dimension::angular_velocity: return "rad/s";
    case Dimension::energy_per_area: return "J/m^2";
    case Dimension::force: return "N";
    case Dimension::mass_per_area: return "kg/m^2";
  }
  return "";
}

std::string_view units_for(Dimension d) {
  switch (d) {
    case Dimension::dimensionless: return "a plain number";
    case Dimension::length: return "m, cm, mm, um, km";
    case Dimension::stress: return "Pa, kPa, MPa, GPa";
    case Dimension::stiffness: return "Pa/m, kPa/m, MPa/m, GPa/m, MPa/mm";
    case Dimension::angle: return "deg, rad";
    case Dimension::time: return "s, ms, min, h";
    case Dimension::velocity: return "m/s, mm/s, mm/min";
    case Dimension::acceleration: return "m/s2, g";
    case Dimension::density: return "kg/m3, g/cm3";
    case Dimension::frequency: return "Hz";
    case Dimension::angular_velocity: return "rad/s, deg/s";
    case Dimension::energy_per_area: return "J/m2";
    case Dimension::force: return "N, kN, MN";
    case Dimension::mass_per_area: return "kg/m2, kg/m^2, t/m2";
  }
  return "";
}

double parse_quantity(std::string_view text, Dimension want) {
  const std::string_view s = trim(text);
  double value = 0.0;
  const char* begin = s.data();
  const char* end = s.data() + s.size();
  auto [ptr, ec] = std::from_chars(begin, end, value);
  if (ec != std::errc() || ptr == begin) {
    throw InputError("'" + std::string(text) + "' does not start with a number");
  }
  const std::string_view unit = trim(std::string_view(ptr, static_cast<size_t>(end - ptr)));
  if (!std::isfinite(value)) throw InputError("'" + std::string(text) + "' is not a finite number");
  if (unit.empty()) {
    if (want == Dimension::dimensionless) return value;
    throw InputError("'" + std::string(text) + "' has no unit; a " +
                     std::string(dimension_name(want)) + " needs one of: " +
                     std::string(units_for(want)));
  }
  for (const auto& u : kUnits) {
    if (u.symbol == unit) {
      if (u.dim != want) {
        throw InputError("unit '" + std::string(unit) + "' is a " + std::string(dimension_name(u.dim)) +
                         ", but a " + std::string(dimension_name(want)) +
                         " is expected (valid units: " + std::string(units_for(want)) + ")");
      }
      // One central check: a value that is finite as written can still overflow on conversion
      // ("1e308 GPa/m"), and an inf stiffness or size later makes the engine loop or allocate
      // without bound, so it is refused here for every key read with a unit.
      const double si = value * u.to_si;
      if (!std::isfinite(si)) {
        throw InputError("'" + std::string(text) + "' overflows when converted to " +
                         std::string(si_unit(want)) + "; the largest magnitude is about " +
                         round_trip_text(std::numeric_limits<double>::max() / u.to_si) + " " + std::string(unit));
      }
      return si;
    }
  }
  throw InputError("unknown unit '" + std::string(unit) + "'; for a " +
                   std::string(dimension_name(want)) + " use one of: " +
                   std::string(units_for(want)));
}

std::string round_trip_text(double v) {
  char buf[64];
  auto [end, ec] = std::to_chars(buf, buf + sizeof(buf), v);
  (void)ec;  // 64 characters hold any double
  return std::string(buf, end);
}

std::string format_quantity(double v, Dimension d) {
  std::ostringstream os;
  os.precision(6);
  switch (d) {
    case Dimension::angle: os << v / kDeg << " deg"; break;
    case Dimension::stress: os << v / 1e6 << " MPa"; break;
    case Dimension::stiffness: os << v / 1e9 << " GPa/m"; break;
    case Dimension::length: os << v << " m"; break;
    default:
      os << v;
      if (d != Dimension::dimensionless) os << ' ' << si_unit(d);
  }
  return os.str();
}

}  // namespace rockdem
