#include "framework/io/calibration_file.hpp"

#include <algorithm>
#include <fstream>

#include <nlohmann/json.hpp>

#include "framework/core/error.hpp"
#include "framework/core/names.hpp"
#include "framework/core/si_raw_value.hpp"

namespace rockdem {
namespace {

using json = nlohmann::json;

const ParamInfo* find_info(const std::vector<ParamInfo>& infos, const std::string& name) {
  const auto it = std::find_if(infos.begin(), infos.end(), [&](const ParamInfo& i) { return i.name == name; });
  return it == infos.end() ? nullptr : &*it;
}

std::string param_names(const std::vector<ParamInfo>& infos) {
  std::vector<std::string> names;
  for (const auto& i : infos) names.push_back(i.name);
  return join_names(names);
}

// One JSON value as the RawValue a case file would give: reals in SI (si_raw_value), choices as
// names, booleans, integers.
// Returns false for null (nlohmann writes an infinite default such as kn_max = inf as null: the
// law's default stands).
bool to_raw(const json& v, const ParamInfo& info, const std::string& where, RawValue& out) {
  out.where = where;
  if (v.is_null()) return false;
  if (info.kind == "real") {
    if (!v.is_number()) throw InputError(where + ": '" + info.name + "' must be a number (SI units), not " + v.dump());
    out = si_raw_value(v.get<double>(), info.dim, where);
  } else if (info.kind == "choice") {
    if (!v.is_string()) throw InputError(where + ": '" + info.name + "' must be one of " + info.range_text() + ", not " + v.dump());
    out.value = v.get<std::string>();
  } else if (info.kind == "bool") {
    if (!v.is_boolean()) throw InputError(where + ": '" + info.name + "' must be true or false, not " + v.dump());
    out.value = v.get<bool>();
  } else {
    if (!v.is_number_integer()) throw InputError(where + ": '" + info.name + "' must be an integer, not " + v.dump());
    out.value = v.get<std::int64_t>();
  }
  return true;
}

const json& member(const json& j, const char* key, const std::string& file, const std::string& what) {
  if (!j.is_object() || !j.contains(key))
    throw InputError(file + ": no '" + std::string(key) + "' in " + what +
                     "; a calibration is the JSON of `rockdem calibrate --json` or `rockdem diagnose --json`");
  return j.at(key);
}

}  // namespace

CalibratedJoint read_calibrated_joint(const std::string& path, const std::string& where) {
  std::ifstream in(path);
  if (!in) throw InputError(where + ": calibration file '" + path + "' cannot be read (it does not exist or is not readable)");
  json j;
  try {
    j = json::parse(in);
  } catch (const json::exception& e) {
    throw InputError(path + ": not valid JSON (" + std::string(e.what()) + ")");
  }
  if (!j.is_object()) throw InputError(path + ": expected a JSON object (the output of `rockdem calibrate --json` or `rockdem diagnose --json`)");
  CalibratedJoint c;
  c.file = path;
  const json* body = &j;
  std::string body_name = "the file";
  if (j.contains("base_law")) {  // rockdem diagnose: the last rung of its ladder
    c.source = "diagnose";
    c.law = member(j, "base_law", path, body_name).get<std::string>();
    body = &member(j, "final", path, body_name);
    body_name = "'final'";
  } else {
    c.source = "calibrate";
    const json& law = member(j, "law", path, body_name);
    if (!law.is_string()) throw InputError(path + ": 'law' must be a law's name, not " + law.dump());
    c.law = law.get<std::string>();
  }
  if (j.contains("status") && j["status"] == "failed")
    throw InputError(path + ": this calibration failed (status \"failed\"); its parameters are not a fitted joint");
  const auto& law_entry = JointLawRegistry::instance().get(c.law, "joint law", path);
  std::vector<const EffectRegistry::Entry*> effect_entries;
  if (body->contains("effects")) {
    for (const auto& e : body->at("effects")) {
      if (!e.is_string()) throw InputError(path + ": " + body_name + " effects: expected effect names, not " + e.dump());
      EffectSpec es;
      es.name = e.get<std::string>();
      es.where = path + " effects";
      effect_entries.push_back(&EffectRegistry::instance().get(es.name, "effect", path + " " + body_name + " effects"));
      c.effects.push_back(std::move(es));
    }
  }
  // A qualified name: "param" of the law or "effect.param".
  auto place = [&](const std::string& name, const json& v, const std::string& section) {
    const std::string at = path + " " + section + "." + name;
    const auto dot = name.find('.');
    RawValue raw;
    if (dot == std::string::npos) {
      const ParamInfo* info = find_info(law_entry.params, name);
      if (!info)
        throw InputError(at + ": joint law '" + c.law + "' has no parameter '" + name + "'; its parameters: " +
                         param_names(law_entry.params));
      if (to_raw(v, *info, at, raw)) c.params[name] = raw;
      return;
    }
    const std::string effect = name.substr(0, dot), pname = name.substr(dot + 1);
    for (std::size_t e = 0; e < c.effects.size(); ++e) {
      if (c.effects[e].name != effect) continue;
      const ParamInfo* info = find_info(effect_entries[e]->params, pname);
      if (!info)
        throw InputError(at + ": effect '" + effect + "' has no parameter '" + pname + "'; its parameters: " +
                         param_names(effect_entries[e]->params));
      if (to_raw(v, *info, at, raw)) c.effects[e].params[pname] = raw;
      return;
    }
    throw InputError(at + ": effect '" + effect + "' is not among the calibration's effects");
  };
  const json& params = member(*body, "params", path, body_name);
  if (!params.is_object()) throw InputError(path + ": 'params' must be an object {name: value}");
  for (const auto& [name, v] : params.items()) place(name, v, "params");
  // Choices, switches and counts the fit ran with (files written before they were recorded have
  // none: the laws' defaults then stand, and the notes of the run say so).
  if (body->contains("settings")) {
    const json& settings = body->at("settings");
    if (!settings.is_object()) throw InputError(path + ": 'settings' must be an object {name: value}");
    for (const auto& [name, v] : settings.items()) place(name, v, "settings");
  }
  return c;
}

void merge_calibration(const CalibratedJoint& c, std::string& law, const std::string& law_where, RawValues& params,
                       std::vector<EffectSpec>& effects) {
  if (!law.empty() && law != c.law)
    throw InputError(law_where + ": law '" + law + "' but the calibration '" + c.file + "' is of a " + c.law +
                     " joint; remove 'law' (the calibration names it) or name a calibration of " + law);
  law = c.law;
  RawValues merged = c.params;
  for (const auto& [k, v] : params) merged[k] = v;  // the case's own values win
  params = std::move(merged);
  std::vector<EffectSpec> out = c.effects;
  for (auto& e : effects) {
    auto it = std::find_if(out.begin(), out.end(), [&](const EffectSpec& o) { return o.name == e.name; });
    if (it == out.end()) {
      out.push_back(std::move(e));
      continue;
    }
    for (const auto& [k, v] : e.params) it->params[k] = v;
    it->where = e.where;
  }
  effects = std::move(out);
}

}  // namespace rockdem
