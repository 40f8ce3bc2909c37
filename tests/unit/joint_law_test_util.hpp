#pragma once
// Helpers for joint-law tests: build models from "key = value-with-unit" pairs, drive them with
// the element driver, and pick values out of the output rows.
#include <cmath>
#include <cstring>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "framework/io/measurement_csv.hpp"
#include "framework/lab/element_driver.hpp"
#include "framework/plugin_api/joint_law.hpp"

namespace rockdem::testutil {

// Values are written as in a case file: quantities with units, choices by name, "true"/"false".
inline RawValues values(std::initializer_list<std::pair<std::string, std::string>> kv) {
  RawValues out;
  for (const auto& [k, v] : kv) {
    RawValue r;
    r.where = "test key " + k;
    if (v == "true" || v == "false") {
      r.value = v == "true";
    } else {
      r.value = v;
    }
    out[k] = r;
  }
  return out;
}

inline std::unique_ptr<JointModel> model(const std::string& law, const RawValues& params,
                                         std::vector<EffectSpec> effects = {}) {
  return make_joint_model(law, params, effects, "test");
}

// The report's section-3 joints (sigma_n = 3 MPa); kn where section 3 gives none is test 9's.
inline RawValues mc_report(std::initializer_list<std::pair<std::string, std::string>> extra = {}) {
  RawValues v = values({{"kn", "35.964 GPa/m"}, {"ks", "16.93 GPa/m"}, {"friction", "38 deg"}, {"dilation_angle", "2.4 deg"}});
  for (auto& [k, r] : values(extra)) v[k] = r;
  return v;
}
inline RawValues bb_report(std::initializer_list<std::pair<std::string, std::string>> extra = {}) {
  RawValues v = values({{"kn", "35.964 GPa/m"}, {"ks", "16.929 GPa/m"}, {"jrc", "7.1"}, {"jcs", "170.5 MPa"},
                        {"residual_friction", "28.4 deg"}, {"lab_length", "0.2032 m"}});
  for (auto& [k, r] : values(extra)) v[k] = r;
  return v;
}
inline RawValues cy_report(std::initializer_list<std::pair<std::string, std::string>> extra = {}) {
  RawValues v = values({{"kn", "29.361 GPa/m"}, {"kn_min", "29.361 GPa/m"}, {"kn_max", "46.109 GPa/m"},
                        {"kn_exponent", "0.6783"}, {"ks", "29.312 GPa/m"}, {"initial_friction", "39.3 deg"},
                        {"friction", "33.5 deg"}, {"roughness", "0.0175 m"}});
  for (auto& [k, r] : values(extra)) v[k] = r;
  return v;
}

inline ElementStage cnl(double sigma_n, ShearPath path) {
  ElementStage s;
  s.normal_stress = sigma_n;
  s.path = std::move(path);
  return s;
}

// Rows of `f` in stage `stage` with index range helpers.
inline double max_tau(const MeasurementFile& f, std::size_t from, std::size_t to) {
  double m = -1e300;
  for (std::size_t i = from; i < to; ++i) m = std::max(m, f.rows[i].shear_stress_MPa);
  return m;
}
inline double min_tau(const MeasurementFile& f, std::size_t from, std::size_t to) {
  double m = 1e300;
  for (std::size_t i = from; i < to; ++i) m = std::min(m, f.rows[i].shear_stress_MPa);
  return m;
}
// Index of the first row at or after `from` whose shear displacement is within tol of u_mm.
inline std::size_t row_at(const MeasurementFile& f, double u_mm, std::size_t from = 0, double tol = 1e-6) {
  for (std::size_t i = from; i < f.rows.size(); ++i)
    if (std::abs(f.rows[i].shear_disp_mm - u_mm) <= tol) return i;
  return f.rows.size();
}

template <class State>
State law_state(const JointStateBlock& b) {
  State s;
  std::memcpy(&s, b.bytes.data(), sizeof(State));
  return s;
}

}  // namespace rockdem::testutil
