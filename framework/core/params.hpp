#pragma once
// Typed, documented parameters (MOOSE-style): a law, effect or material declares each parameter
// once, bound to a member of its Params struct, with its dimension, default, range and meaning.
// The same declaration validates case files and prints `rockdem describe`.
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "framework/core/error.hpp"
#include "framework/core/units.hpp"

namespace rockdem {

// One raw value as written by the user, with where it was written (for messages).
struct RawValue {
  std::variant<double, std::int64_t, bool, std::string> value;
  std::string where;  // e.g. "cases/x.toml:12 key joints.kn"
};
using RawValues = std::map<std::string, RawValue>;

inline constexpr double kInf = std::numeric_limits<double>::infinity();

// Description of one parameter, independent of the struct it binds to (for listings).
struct ParamInfo {
  std::string name;
  std::string kind;  // "real", "choice", "bool", "integer"
  Dimension dim = Dimension::dimensionless;
  std::optional<double> default_real;  // SI
  std::string default_text;            // for choice/bool/integer
  double min = -kInf, max = kInf;
  bool min_open = false, max_open = false;
  std::vector<std::string> choices;
  std::string doc;
  bool required() const { return kind == "real" ? !default_real.has_value() : default_text.empty(); }
  std::string range_text() const;
  std::string default_display() const;
};

template <class P>
struct Param {
  ParamInfo info;
  std::variant<double P::*, int P::*, bool P::*> member;
};

// Builders used inside a Params struct's `spec()`:
//   real("kn", &Params::kn, Dimension::stiffness, "normal stiffness").positive().def(10e9)
template <class P>
class ParamBuilder {
 public:
  explicit ParamBuilder(Param<P> p) : p_(std::move(p)) {}
  ParamBuilder& def(double v) { p_.info.default_real = v; return *this; }
  ParamBuilder& def_text(std::string v) { p_.info.default_text = std::move(v); return *this; }
  ParamBuilder& min(double v, bool open = false) { p_.info.min = v; p_.info.min_open = open; return *this; }
  ParamBuilder& max(double v, bool open = false) { p_.info.max = v; p_.info.max_open = open; return *this; }
  ParamBuilder& positive() { return min(0.0, true); }
  ParamBuilder& non_negative() { return min(0.0, false); }
  operator Param<P>() const { return p_; }  // NOLINT: builder converts implicitly
 private:
  Param<P> p_;
};

template <class P>
ParamBuilder<P> real(std::string name, double P::*m, Dimension d, std::string doc) {
  Param<P> p{ParamInfo{}, m};
  p.info.name = std::move(name);
  p.info.kind = "real";
  p.info.dim = d;
  p.info.doc = std::move(doc);
  return ParamBuilder<P>(p);
}
template <class P>
ParamBuilder<P> choice(std::string name, int P::*m, std::vector<std::string> choices,
                       std::string default_choice, std::string doc) {
  Param<P> p{ParamInfo{}, m};
  p.info.name = std::move(name);
  p.info.kind = "choice";
  p.info.choices = std::move(choices);
  p.info.default_text = std::move(default_choice);
  p.info.doc = std::move(doc);
  return ParamBuilder<P>(p);
}
template <class P>
ParamBuilder<P> flag(std::string name, bool P::*m, bool default_value, std::string doc) {
  Param<P> p{ParamInfo{}, m};
  p.info.name = std::move(name);
  p.info.kind = "bool";
  p.info.default_text = default_value ? "true" : "false";
  p.info.doc = std::move(doc);
  return ParamBuilder<P>(p);
}
template <class P>
ParamBuilder<P> integer(std::string name, int P::*m, int default_value, std::string doc) {
  Param<P> p{ParamInfo{}, m};
  p.info.name = std::move(name);
  p.info.kind = "integer";
  p.info.default_text = std::to_string(default_value);
  p.info.doc = std::move(doc);
  return ParamBuilder<P>(p);
}

// A physical quantity from a raw value: a string "<number> <unit>" of dimension `d`, or a plain
// number where `d` is dimensionless. `subject` names it in messages ("parameter 'kn' of ...").
double quantity_value(const RawValue& raw, Dimension d, const std::string& subject);
// Parse one raw value for a parameter (unit conversion and range check). `owner` names the law,
// effect or block the parameter belongs to, for messages.
double parse_real(const ParamInfo& info, const RawValue& raw, const std::string& owner);
int parse_choice(const ParamInfo& info, const RawValue& raw, const std::string& owner);
bool parse_flag(const ParamInfo& info, const RawValue& raw, const std::string& owner);
int parse_integer(const ParamInfo& info, const RawValue& raw, const std::string& owner);
// Unknown keys: an error that lists the valid names.
void check_known_keys(const RawValues& values, const std::vector<ParamInfo>& infos,
                      const std::string& owner);
void check_range(const ParamInfo& info, double v, const std::string& where, const std::string& owner);

template <class P>
std::vector<ParamInfo> param_infos() {
  std::vector<ParamInfo> out;
  for (const auto& p : P::spec()) out.push_back(p.info);
  return out;
}

// Fill a Params struct from user values; defaults where allowed; every problem is an InputError
// naming the key, where it was written, and what is valid. `missing_where` names the table.
template <class P>
P bind_params(const RawValues& values, const std::string& owner, const std::string& missing_where) {
  const auto spec = P::spec();
  std::vector<ParamInfo> infos;
  for (const auto& p : spec) infos.push_back(p.info);
  check_known_keys(values, infos, owner);
  P out{};
  for (const auto& p : spec) {
    auto it = values.find(p.info.name);
    std::visit(
        [&](auto m) {
          using M = std::remove_reference_t<decltype(out.*m)>;
          if (it == values.end()) {
            if (p.info.required()) {
              throw InputError(missing_where + ": missing required parameter '" + p.info.name +
                               "' of " + owner + " (" + p.info.doc + ", " +
                               std::string(dimension_name(p.info.dim)) + ", range " +
                               p.info.range_text() + ")");
            }
            if constexpr (std::is_same_v<M, double>) {
              out.*m = *p.info.default_real;
            } else if constexpr (std::is_same_v<M, bool>) {
              out.*m = p.info.default_text == "true";
            } else {
              if (p.info.kind == "choice") {
                int idx = 0;
                for (size_t i = 0; i < p.info.choices.size(); ++i)
                  if (p.info.choices[i] == p.info.default_text) idx = static_cast<int>(i);
                out.*m = idx;
              } else {
                out.*m = std::stoi(p.info.default_text);
              }
            }
            return;
          }
          if constexpr (std::is_same_v<M, double>) {
            out.*m = parse_real(p.info, it->second, owner);
          } else if constexpr (std::is_same_v<M, bool>) {
            out.*m = parse_flag(p.info, it->second, owner);
          } else {
            out.*m = p.info.kind == "choice" ? parse_choice(p.info, it->second, owner)
                                             : parse_integer(p.info, it->second, owner);
          }
        },
        p.member);
  }
  if constexpr (requires(const P& q) { q.validate(); }) {
    out.validate();  // cross-parameter checks; throws InputError with the owner's name
  }
  return out;
}

}  // namespace rockdem
