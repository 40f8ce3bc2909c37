#include "framework/core/params.hpp"

#include <sstream>

#include "framework/core/did_you_mean.hpp"
#include "framework/core/names.hpp"

namespace rockdem {
namespace {
std::string num(double v) {
  std::ostringstream os;
  os.precision(6);
  os << v;
  return os.str();
}
std::string show(double si, Dimension d) {
  if (std::isinf(si)) return si > 0 ? "inf" : "-inf";
  return format_quantity(si, d);
}
}  // namespace

std::string ParamInfo::range_text() const {
  if (kind == "choice") {
    std::string s = "one of {";
    for (size_t i = 0; i < choices.size(); ++i) s += (i ? ", " : "") + choices[i];
    return s + "}";
  }
  if (kind == "bool") return "true or false";
  if (kind == "integer") return "an integer";
  return std::string(min_open ? "(" : "[") + show(min, dim) + ", " + show(max, dim) +
         (max_open ? ")" : "]");
}

std::string ParamInfo::default_display() const {
  if (kind == "real") return default_real ? show(*default_real, dim) : "(required)";
  return default_text.empty() ? "(required)" : default_text;
}

void check_range(const ParamInfo& info, double v, const std::string& where, const std::string& owner) {
  const bool below = info.min_open ? v <= info.min : v < info.min;
  const bool above = info.max_open ? v >= info.max : v > info.max;
  if (below || above || std::isnan(v)) {
    throw InputError(where + ": parameter '" + info.name + "' of " + owner + " = " +
                     show(v, info.dim) + " is out of range; valid range is " + info.range_text() +
                     " (" + info.doc + ")");
  }
}

double quantity_value(const RawValue& raw, Dimension d, const std::string& subject) {
  double v = 0.0;
  if (const auto* s = std::get_if<std::string>(&raw.value)) {
    try {
      return parse_quantity(*s, d);
    } catch (const InputError& e) {
      throw InputError(raw.where + ": " + subject + ": " + e.what());
    }
  } else if (const auto* x = std::get_if<double>(&raw.value)) {
    v = *x;
  } else if (const auto* i = std::get_if<std::int64_t>(&raw.value)) {
    v = static_cast<double>(*i);
  } else {
    throw InputError(raw.where + ": " + subject + " must be a number" +
                     (d == Dimension::dimensionless ? std::string() :
                      " with a unit, as a string like \"1.5 " + std::string(si_unit(d)) + "\""));
  }
  // TOML allows nan and inf literals; no rockdem quantity means them.
  if (!std::isfinite(v)) throw InputError(raw.where + ": " + subject + " must be a finite number, not " + num(v));
  if (d != Dimension::dimensionless) {
    throw InputError(raw.where + ": " + subject + " = " + num(v) + " has no unit; a " +
                     std::string(dimension_name(d)) + " is written as a string with one of: " +
                     std::string(units_for(d)) + " (e.g. \"" + num(v) + " " + std::string(si_unit(d)) + "\")");
  }
  return v;
}

double parse_real(const ParamInfo& info, const RawValue& raw, const std::string& owner) {
  const double v = quantity_value(raw, info.dim, "parameter '" + info.name + "' of " + owner);
  check_range(info, v, raw.where, owner);
  return v;
}

int parse_choice(const ParamInfo& info, const RawValue& raw, const std::string& owner) {
  const auto* s = std::get_if<std::string>(&raw.value);
  if (s) {
    for (size_t i = 0; i < info.choices.size(); ++i)
      if (info.choices[i] == *s) return static_cast<int>(i);
  }
  throw InputError(raw.where + ": parameter '" + info.name + "' of " + owner + " must be " +
                   info.range_text() + (s ? ", not '" + *s + "'" : std::string()));
}

bool parse_flag(const ParamInfo& info, const RawValue& raw, const std::string& owner) {
  if (const auto* b = std::get_if<bool>(&raw.value)) return *b;
  throw InputError(raw.where + ": parameter '" + info.name + "' of " + owner + " must be true or false");
}

int parse_integer(const ParamInfo& info, const RawValue& raw, const std::string& owner) {
  if (const auto* i = std::get_if<std::int64_t>(&raw.value)) {
    check_range(info, static_cast<double>(*i), raw.where, owner);
    return static_cast<int>(*i);
  }
  throw InputError(raw.where + ": parameter '" + info.name + "' of " + owner + " must be an integer");
}

void check_known_keys(const RawValues& values, const std::vector<ParamInfo>& infos,
                      const std::string& owner) {
  for (const auto& [key, raw] : values) {
    bool known = false;
    for (const auto& i : infos) known = known || i.name == key;
    if (!known) {
      throw InputError(raw.where + ": unknown parameter '" + key + "' for " + owner +
                       did_you_mean(key, infos, &ParamInfo::name) + "; valid parameters: " + join_names(infos, &ParamInfo::name));
    }
  }
}

}  // namespace rockdem
