// A calibration's JSON read back as a joint (calibration_file.hpp): the joint rebuilt from the
// file of `rockdem calibrate` answers as the fitted model did, bit for bit; a diagnose JSON gives
// its law, effects and effect parameters; a case's own keys are set over the file's; files that
// cannot be a fitted joint are refused with the file and the entry named.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>

#include "tests/unit/noisy_record.hpp"
#include "framework/analysis/calibration.hpp"
#include "framework/core/error.hpp"
#include "framework/io/calibration_file.hpp"
#include "framework/lab/element_driver.hpp"
#include "framework/plugin_api/joint_law.hpp"

using namespace rockdem;
namespace fs = std::filesystem;

namespace {

RawValue q(const char* text) { return RawValue{std::string(text), "test"}; }

std::string write_file(const std::string& name, const std::string& text) {
  const fs::path p = fs::temp_directory_path() / ("rockdem_calibration_file_" + std::to_string(::getpid()) + "_" + name);
  std::ofstream(p) << text;
  return p.string();
}

std::string error_of(const std::string& path) {
  try {
    read_calibrated_joint(path, "case.toml:3 key 'joints.j.calibration'");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

std::string str(const RawValue& v) { return std::get<std::string>(v.value); }

}  // namespace

TEST(CalibrationFile, AJointRebuiltFromCalibrateJsonAnswersAsTheFittedModel) {
  // A Mohr-Coulomb record with reversible dilation (a setting, not a fitted number), fitted.
  const RawValues truth{{"kn", q("40 GPa/m")}, {"ks", q("12 GPa/m")}, {"friction", q("36 deg")},
                        {"dilation_angle", q("5 deg")}, {"dilation", q("reversible")}};
  const auto made = make_joint_model("mohr_coulomb", truth, {}, "test");
  const MeasurementFile f = testutil::noisy_two_stage_record(*made, 2.5e-5, 4, true, 3, 1.0);
  CalibrationOptions o;
  o.law = "mohr_coulomb";
  o.element.max_step = 2.5e-5;
  o.element.length = 0.2;
  o.fit_step = 5e-5;
  o.law_values["dilation"] = q("reversible");
  const Segmentation seg = segment(f);
  const CalibrationResult r = calibrate(f, seg, o);
  ASSERT_NE(r.status, "failed");
  EXPECT_EQ(r.settings.at("dilation"), "reversible");

  const std::string path = write_file("mc.json", to_json(r).dump(2));
  const CalibratedJoint c = read_calibrated_joint(path, "test");
  EXPECT_EQ(c.source, "calibrate");
  EXPECT_EQ(c.law, "mohr_coulomb");
  EXPECT_EQ(str(c.params.at("dilation")), "reversible");
  EXPECT_NE(c.params.at("kn").where.find("params.kn"), std::string::npos);

  // The rebuilt joint on the record's path gives the fitted model's record exactly.
  const auto rebuilt = make_joint_model(c.law, c.params, c.effects, "test");
  ElementDriver d(*rebuilt, o.element);
  const MeasurementFile m = d.run(stages_from_data(f, seg));
  ASSERT_EQ(m.rows.size(), r.model.rows.size());
  for (std::size_t i = 0; i < m.rows.size(); ++i) {
    ASSERT_EQ(m.rows[i].shear_stress_MPa, r.model.rows[i].shear_stress_MPa) << "row " << i;
    ASSERT_EQ(m.rows[i].normal_disp_mm, r.model.rows[i].normal_disp_mm) << "row " << i;
  }
  fs::remove(path);
}

TEST(CalibrationFile, DiagnoseJsonGivesTheLastRungsLawEffectsAndParameters) {
  const std::string path = write_file("diag.json", R"({
    "base_law": "continuously_yielding",
    "final": {"effects": ["reverse_shear_degradation", "dilation_recovery"],
              "params": {"kn": 3e10, "ks": 2e10, "initial_friction": 0.7, "friction": 0.55, "roughness": 0.01,
                         "kn_max": null, "reverse_shear_degradation.weight": 0.8,
                         "dilation_recovery.residual_fraction": 0.2},
              "settings": {"dilation": "reversible", "dilation_recovery.enabled": true},
              "nrmse": {"combined": 0.05}}})");
  const CalibratedJoint c = read_calibrated_joint(path, "test");
  EXPECT_EQ(c.source, "diagnose");
  EXPECT_EQ(c.law, "continuously_yielding");
  ASSERT_EQ(c.effects.size(), 2u);
  EXPECT_EQ(c.effects[0].name, "reverse_shear_degradation");
  EXPECT_EQ(std::get<double>(c.effects[0].params.at("weight").value), 0.8);
  EXPECT_EQ(std::get<double>(c.effects[1].params.at("residual_fraction").value), 0.2);
  EXPECT_TRUE(std::get<bool>(c.effects[1].params.at("enabled").value));
  EXPECT_EQ(str(c.params.at("kn")), "30000000000 Pa/m");
  EXPECT_EQ(str(c.params.at("friction")), "0.55000000000000004 rad");
  EXPECT_EQ(c.params.count("kn_max"), 0u);  // null: an infinite default, left to the law
  EXPECT_NO_THROW(make_joint_model(c.law, c.params, c.effects, "test"));

  // The case's keys over the file's: a parameter replaced, an effect's parameter replaced, an
  // effect added after the calibration's.
  std::string law;
  RawValues params{{"kn", q("10 GPa/m")}};
  std::vector<EffectSpec> effects{{"reverse_shear_degradation", {{"weight", RawValue{1.0, "case"}}}, "case"},
                                  {"directional_wear", {}, "case"}};
  merge_calibration(c, law, "case", params, effects);
  EXPECT_EQ(law, "continuously_yielding");
  EXPECT_EQ(str(params.at("kn")), "10 GPa/m");
  EXPECT_EQ(str(params.at("ks")), "20000000000 Pa/m");
  ASSERT_EQ(effects.size(), 3u);
  EXPECT_EQ(std::get<double>(effects[0].params.at("weight").value), 1.0);
  EXPECT_EQ(effects[2].name, "directional_wear");
  EXPECT_NO_THROW(make_joint_model(law, params, effects, "test"));

  // A law named in the case must be the calibration's.
  std::string other = "barton_bandis";
  RawValues none;
  std::vector<EffectSpec> no_effects;
  try {
    merge_calibration(c, other, "case.toml:4 key 'joints.j.law'", none, no_effects);
    FAIL() << "a Barton-Bandis entry took a Continuously-Yielding calibration";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("case.toml:4"), std::string::npos) << m;
    EXPECT_NE(m.find("continuously_yielding"), std::string::npos) << m;
    EXPECT_NE(m.find("barton_bandis"), std::string::npos) << m;
  }
  fs::remove(path);
}

TEST(CalibrationFile, FilesThatAreNotAFittedJointAreRefusedWithTheirPlace) {
  struct Bad {
    const char* name;
    const char* text;
    const char* expect;
  };
  const Bad bad[] = {
      {"syntax.json", "{\"law\": \"mohr_coulomb\", ", "not valid JSON"},
      {"array.json", "[1, 2]", "expected a JSON object"},
      {"nolaw.json", "{\"params\": {}}", "no 'law'"},
      {"unknown_law.json", "{\"law\": \"mohr_colomb\", \"params\": {}}", "did you mean 'mohr_coulomb'"},
      {"unknown_param.json", "{\"law\": \"mohr_coulomb\", \"params\": {\"frction\": 0.6}}", "has no parameter 'frction'"},
      {"unknown_effect.json", "{\"law\": \"mohr_coulomb\", \"effects\": [\"wear\"], \"params\": {}}", "unknown effect 'wear'"},
      {"stray_effect.json", "{\"law\": \"mohr_coulomb\", \"params\": {\"dilation_recovery.hysteresis\": 0.5}}",
       "not among the calibration's effects"},
      {"text_value.json", "{\"law\": \"mohr_coulomb\", \"params\": {\"kn\": \"big\"}}", "must be a number"},
      {"failed.json", "{\"law\": \"mohr_coulomb\", \"status\": \"failed\", \"params\": {}}", "failed"},
      {"noparams.json", "{\"law\": \"mohr_coulomb\"}", "no 'params'"},
  };
  for (const auto& b : bad) {
    const std::string path = write_file(b.name, b.text);
    const std::string m = error_of(path);
    EXPECT_NE(m.find(b.expect), std::string::npos) << b.name << ": " << m;
    EXPECT_NE(m.find(path), std::string::npos) << b.name << ": the message names the file: " << m;
    fs::remove(path);
  }
  const std::string missing = error_of("/nonexistent/fit.json");
  EXPECT_NE(missing.find("case.toml:3 key 'joints.j.calibration'"), std::string::npos) << missing;
  EXPECT_NE(missing.find("cannot be read"), std::string::npos) << missing;
}
