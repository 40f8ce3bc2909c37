#pragma once
// A value in SI units as the RawValue a case file would give, so that a parameter set in code
// (a calibration's trial point, a calibrated joint read back from JSON) goes through the same
// parsing and range checks as one written by hand: "<value> <SI unit>", with the shortest
// decimal text that reads back to the same double (%.17g), or the bare number when dimensionless.
#include <cstdio>
#include <string>

#include "framework/core/params.hpp"
#include "framework/core/units.hpp"

namespace rockdem {

inline RawValue si_raw_value(double v, Dimension d, std::string where) {
  RawValue r;
  if (d == Dimension::dimensionless) {
    r.value = v;
  } else {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.17g %s", v, std::string(si_unit(d)).c_str());
    r.value = std::string(buf);
  }
  r.where = std::move(where);
  return r;
}

}  // namespace rockdem
