#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "framework/core/error.hpp"
#include "framework/io/measurement_csv.hpp"

using namespace rockdem;

namespace {

std::string tmp_path(const std::string& name) {
  return (std::filesystem::temp_directory_path() /
          ("rockdem_meas_" + std::to_string(::getpid()) + "_" + name))
      .string();
}

std::string write_text(const std::string& name, const std::string& text) {
  const std::string p = tmp_path(name);
  std::ofstream(p) << text;
  return p;
}

// Expects an InputError whose message names the file, the line and contains `rule`.
void expect_rejected(const std::string& name, const std::string& text, int line, const std::string& rule) {
  const std::string p = write_text(name, text);
  try {
    read_measurement_csv(p);
    ADD_FAILURE() << "accepted a file breaking: " << rule;
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find(p + ":" + std::to_string(line) + ":"), std::string::npos) << m;
    EXPECT_NE(m.find(rule), std::string::npos) << m;
  }
  std::filesystem::remove(p);
}

const char* kHeader = "time_s,stage,normal_stress_MPa,shear_disp_mm,shear_stress_MPa,normal_disp_mm\n";

}  // namespace

TEST(MeasurementCsv, RoundTripsRowsMetadataAndExtraColumns) {
  MeasurementFile f;
  f.metadata = {{"specimen", "test09"}, {"joint_length_m", "0.2032"}, {"source", "rockdem"}};
  f.extra_columns = {"kn_GPa_per_m"};
  for (int i = 0; i < 50; ++i) {
    const double t = 0.1 * i;
    f.rows.push_back({t, 1 + i / 25, 3.0 + 1e-7 * i, 0.01 * i, std::sin(0.3 * i) * 2.3439, -1e-3 * i / 3.0});
    f.extra.push_back({35.964 + i});
  }
  const std::string p = tmp_path("roundtrip.csv");
  write_measurement_csv(p, f);
  const MeasurementFile g = read_measurement_csv(p);
  ASSERT_EQ(g.rows.size(), f.rows.size());
  EXPECT_EQ(g.metadata, f.metadata);
  EXPECT_EQ(g.extra_columns, f.extra_columns);
  for (std::size_t i = 0; i < f.rows.size(); ++i) {
    EXPECT_EQ(g.rows[i].time_s, f.rows[i].time_s);  // shortest round-trip formatting is exact
    EXPECT_EQ(g.rows[i].stage, f.rows[i].stage);
    EXPECT_EQ(g.rows[i].normal_stress_MPa, f.rows[i].normal_stress_MPa);
    EXPECT_EQ(g.rows[i].shear_disp_mm, f.rows[i].shear_disp_mm);
    EXPECT_EQ(g.rows[i].shear_stress_MPa, f.rows[i].shear_stress_MPa);
    EXPECT_EQ(g.rows[i].normal_disp_mm, f.rows[i].normal_disp_mm);
    ASSERT_EQ(g.extra[i].size(), 1u);
    EXPECT_EQ(g.extra[i][0], f.extra[i][0]);
  }
  std::filesystem::remove(p);
}

TEST(MeasurementCsv, ColumnsInAnyOrderWithExtrasAndIrregularSampling) {
  const std::string p = write_text("order.csv",
                                   "# specimen: lab7\n# note without colon\n"
                                   "stage, shear_disp_mm,lvdt2,time_s,normal_disp_mm,shear_stress_MPa,normal_stress_MPa\r\n"
                                   "1,0.0,7,0.0,0.0,0.0,5.0\r\n"
                                   "1,0.5,8,0.5,0.01,1.2,5.0\r\n"
                                   "\n"
                                   "2,+0.1,9,0.5,-0.002,-0.3,6\r\n"
                                   "2,0.2,9,10.0,1e-3,-0.4,6\r\n");
  const auto f = read_measurement_csv(p);
  ASSERT_EQ(f.rows.size(), 4u);
  EXPECT_EQ(f.metadata.size(), 2u);
  EXPECT_EQ(f.metadata[0].first, "specimen");
  EXPECT_EQ(f.metadata[0].second, "lab7");
  EXPECT_EQ(f.metadata[1].first, "note without colon");
  ASSERT_EQ(f.extra_columns.size(), 1u);
  EXPECT_EQ(f.extra_columns[0], "lvdt2");
  EXPECT_EQ(f.rows[1].shear_disp_mm, 0.5);
  EXPECT_EQ(f.rows[1].shear_stress_MPa, 1.2);
  EXPECT_EQ(f.rows[1].normal_disp_mm, 0.01);
  EXPECT_EQ(f.rows[2].stage, 2);
  EXPECT_EQ(f.rows[2].shear_disp_mm, 0.1);
  EXPECT_EQ(f.rows[3].time_s, 10.0);
  EXPECT_EQ(f.extra[3][0], 9.0);
  std::filesystem::remove(p);
}

TEST(MeasurementCsv, RejectsBrokenRulesNamingFileLineAndRule) {
  expect_rejected("missing.csv", "# a: b\ntime_s,stage,normal_stress_MPa,shear_disp_mm,shear_stress_MPa\n1,1,1,1,1\n",
                  2, "missing column 'normal_disp_mm'");
  expect_rejected("nonnum.csv", std::string(kHeader) + "0,1,3,0,0,0\n1,1,3,abc,0,0\n", 3,
                  "non-numeric value 'abc' in column 'shear_disp_mm'");
  expect_rejected("empty_field.csv", std::string(kHeader) + "0,1,3,,0,0\n", 2, "non-numeric value");
  expect_rejected("nan.csv", std::string(kHeader) + "0,1,3,0,0,0\n1,1,3,0,nan,0\n", 3, "NaN in column 'shear_stress_MPa'");
  expect_rejected("backwards.csv", std::string(kHeader) + "0,1,3,0,0,0\n2,1,3,0,0,0\n1.5,1,3,0,0,0\n", 4,
                  "time going backwards");
  expect_rejected("fields.csv", std::string(kHeader) + "0,1,3,0,0\n", 2, "row has 5 fields");
  expect_rejected("stage.csv", std::string(kHeader) + "0,1.5,3,0,0,0\n", 2, "stage must be a positive integer");
  expect_rejected("stage_order.csv", std::string(kHeader) + "0,2,3,0,0,0\n1,1,3,0,0,0\n", 3, "must not decrease");
  expect_rejected("late_comment.csv", std::string(kHeader) + "0,1,3,0,0,0\n# x: y\n", 3, "after the header");
  expect_rejected("dup.csv", "time_s,time_s,stage,normal_stress_MPa,shear_disp_mm,shear_stress_MPa,normal_disp_mm\n", 1,
                  "appears twice");
  expect_rejected("noheader.csv", "# only: metadata\n", 1, "no header line");
}

TEST(MeasurementCsv, MissingFileIsAnInputErrorNamingIt) {
  const std::string p = tmp_path("does_not_exist.csv");
  try {
    read_measurement_csv(p);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(p), std::string::npos);
  }
}

TEST(MeasurementCsv, WriterRefusesRowsThatDoNotMatchTheHeader) {
  MeasurementFile f;
  f.rows = {{0.0, 1, 3.0, 0.0, 0.0, 0.0}, {1.0, 1, 3.0, 0.1, 0.2, 0.0}};
  f.extra_columns = {"a", "b"};
  f.extra = {{1.0, 2.0}};
  const std::string p = tmp_path("mismatch.csv");
  EXPECT_THROW(write_measurement_csv(p, f), InputError);
  f.extra = {{1.0, 2.0}, {3.0}};
  EXPECT_THROW(write_measurement_csv(p, f), InputError);
  EXPECT_FALSE(std::filesystem::exists(p));
  f.extra = {{1.0, 2.0}, {3.0, 4.0}};
  write_measurement_csv(p, f);
  EXPECT_EQ(read_measurement_csv(p).extra[1][1], 4.0);
  std::filesystem::remove(p);
}
