#include <cmath>
#include <cstdio>
#include <sstream>

#include "framework/analysis/calibration.hpp"
#include "framework/analysis/calibration_fit.hpp"

namespace rockdem {

using calibration_detail::kDeg;

nlohmann::json to_json(const CalibrationResult& r) {
  nlohmann::json j;
  j["law"] = r.law;
  j["effects"] = r.effects;
  j["model"] = r.model_description;
  j["status"] = r.status;
  j["converged"] = r.converged;
  j["iterations"] = r.iterations;
  j["evaluations"] = r.evaluations;
  j["increments"] = r.increments;
  j["missed_increments"] = r.missed_increments;
  auto nr = [](const std::array<double, 3>& a) {
    return nlohmann::json{{"shear_stress", a[0]}, {"normal_disp", a[1]}, {"combined", a[2]}};
  };
  j["nrmse"] = nr(r.nrmse);
  j["nrmse_fit_step"] = nr(r.nrmse_fit);
  j["rss"] = r.rss;
  j["n"] = r.n;
  j["k"] = r.k;
  j["bic"] = r.bic;
  j["params"] = nlohmann::json::object();
  j["parameters"] = nlohmann::json::array();
  for (const auto& p : r.params) {
    j["params"][p.name] = p.value;
    nlohmann::json e{{"name", p.name},        {"owner", p.owner},  {"unit", std::string(si_unit(p.dim))},
                     {"value", p.value},      {"start", p.start},  {"free", p.free},
                     {"display", format_quantity(p.value, p.dim)}};
    if (p.free) {
      e["se"] = std::isfinite(p.se) ? nlohmann::json(p.se) : nlohmann::json(nullptr);
      e["lower"] = p.lower;
      e["upper"] = p.upper;
      e["at_bound"] = p.at_bound;
      if (p.profiled())
        e["profile_95"] = {{"lower", p.profile_lower},
                           {"upper", p.profile_upper},
                           {"lower_open", p.profile_lower_open},
                           {"upper_open", p.profile_upper_open},
                           {"fits", p.profile_fits}};
      e["scale"] = p.log_scale ? "log" : "linear";
    }
    j["parameters"].push_back(e);
  }
  j["settings"] = r.settings;
  j["warnings"] = r.warnings;
  j["wall_ms"] = r.wall_ms;
  return j;
}

std::string format_table(const CalibrationResult& r) {
  std::ostringstream os;
  char buf[256];
  os << "parameter                         value          +- s.e.         unit    note\n";
  for (const auto& p : r.params) {
    // Angles in degrees, everything else in SI, so that value and error share one unit.
    const bool ang = p.dim == Dimension::angle;
    const double f = ang ? 1.0 / kDeg : 1.0;
    const std::string unit = ang ? "deg" : std::string(si_unit(p.dim));
    std::string se = p.free ? (std::isfinite(p.se) ? "" : "inf") : "fixed";
    if (p.free && std::isfinite(p.se)) {
      std::snprintf(buf, sizeof buf, "%.4g", p.se * f);
      se = buf;
    }
    std::string note = p.at_bound ? "AT BOUND" : "";
    if (p.free && !std::isfinite(p.se)) note += note.empty() ? "not identifiable" : ", not identifiable";
    if (p.profiled()) {
      char range[160];
      std::snprintf(range, sizeof range, "profile 95 %%: %s%.4g .. %.4g%s", p.profile_lower_open ? "(bound) " : "", p.profile_lower * f,
                    p.profile_upper * f, p.profile_upper_open ? " (bound)" : "");
      note += note.empty() ? range : std::string(", ") + range;
    }
    std::snprintf(buf, sizeof buf, "  %-30s %-14.6g %-15s %-7s %s\n", p.name.c_str(), p.value * f, se.c_str(), unit.c_str(),
                  note.c_str());
    os << buf;
  }
  std::snprintf(buf, sizeof buf,
                "NRMSE: shear stress %.4f, normal displacement %.4f, combined %.4f (at the fitting step: %.4f)\n",
                r.nrmse[0], r.nrmse[1], r.nrmse[2], r.nrmse_fit[2]);
  os << buf;
  std::snprintf(buf, sizeof buf, "fit: %s after %d iterations, %ld model runs, %.0f ms; n = %zu residuals, k = %d, BIC %.1f\n",
                r.status.c_str(), r.iterations, r.evaluations, r.wall_ms, r.n, r.k, r.bic);
  os << buf;
  for (const auto& w : r.warnings) os << "warning: " << w << "\n";
  return os.str();
}

}  // namespace rockdem
