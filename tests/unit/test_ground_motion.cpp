// Accelerogram loading (framework/seismic/ground_motion.hpp): the repository's three records in
// their formats and units, and every bad input refused with file:line, what and what is valid.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "framework/core/error.hpp"
#include "framework/seismic/ground_motion.hpp"

using namespace rockdem;
using namespace rockdem::seismic;

namespace {

const std::string kData = ROCKDEM_SOURCE_DIR "/cases/data/ground_motions/";

RecordLayout layout_of(const std::string& column, const std::string& unit) {
  RecordLayout l;
  l.column = column;
  l.unit = parse_acceleration_unit(unit);
  return l;
}

// The records these tests write go into one folder of this process, removed when it exits (they
// were left in /tmp, a handful per run).
struct Scratch {
  std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("rockdem_gm_" + std::to_string(::getpid()));
  Scratch() { std::filesystem::create_directories(dir); }
  ~Scratch() {
    std::error_code ec;
    std::filesystem::remove_all(dir, ec);
  }
};

std::string write_text(const std::string& name, const std::string& text) {
  static const Scratch scratch;
  const auto p = scratch.dir / name;
  std::ofstream(p) << text;
  return p.string();
}

// Loading must fail with a message holding every one of `parts`.
void expect_rejected(const std::string& path, const RecordLayout& l, std::initializer_list<std::string> parts) {
  try {
    load_ground_motion(path, l);
    ADD_FAILURE() << "accepted " << path;
  } catch (const InputError& e) {
    const std::string m = e.what();
    for (const auto& p : parts) EXPECT_NE(m.find(p), std::string::npos) << "'" << p << "' missing in: " << m;
  }
}

}  // namespace

TEST(GroundMotion, LoadsTheRecordsInTheirUnits) {
  const auto mx = load_ground_motion(kData + "mexico1985_sct_acc_g.txt", layout_of("3", "g"));
  EXPECT_EQ(mx.acc.size(), 8171u);
  EXPECT_NEAR(mx.dt, 0.02, 1e-9);
  EXPECT_NEAR(mx.t0, 0.02, 1e-12);
  const auto ip = peak_index(mx.acc);
  EXPECT_NEAR(mx.acc[ip], 0.17117 * 9.80665, 1e-9);  // E-W PGA 0.1712 g at 58.10 s
  EXPECT_NEAR(mx.t0 + mx.dt * static_cast<double>(ip), 58.10, 1e-6);
  EXPECT_EQ(mx.column_name, "column 3");

  const auto ec = load_ground_motion(kData + "elcentro1940_ns_acc_g.csv", layout_of("acc (g)", "g"));
  EXPECT_EQ(ec.acc.size(), 1560u);
  EXPECT_NEAR(ec.acc[peak_index(ec.acc)], -0.31882 * 9.80665, 1e-9);

  const auto nr = load_ground_motion(kData + "northridge1994_sylmar_acc_mps2.txt", layout_of("", "m/s^2"));
  EXPECT_EQ(nr.acc.size(), 3000u);
  EXPECT_NEAR(nr.acc[peak_index(nr.acc)], 8.2676, 1e-9);
  EXPECT_NEAR(nr.dt * static_cast<double>(peak_index(nr.acc)), 4.20, 1e-9);
}

TEST(GroundMotion, NoTimeColumnNeedsDt) {
  const auto p = write_text("notime.txt", "# one column\n0.1\n0.2\n-0.3\n");
  RecordLayout l = layout_of("1", "m/s2");
  l.time_column = 0;
  expect_rejected(p, l, {"no time column", "dt"});
  l.dt = 0.01;
  const auto g = load_ground_motion(p, l);
  EXPECT_EQ(g.acc.size(), 3u);
  EXPECT_DOUBLE_EQ(g.acc[2], -0.3);
}

TEST(GroundMotion, BadInputNamesFileLineAndWhatIsValid) {
  const auto l2 = layout_of("2", "g");
  expect_rejected(kData + "missing.txt", l2, {"missing.txt", "no such file"});
  expect_rejected(write_text("nan.txt", "0 0.1\n0.02 abc\n0.04 0.2\n"), l2,
                  {"nan.txt:2", "column 2 holds 'abc'", "not a finite number"});
  expect_rejected(write_text("ragged.txt", "0 0.1\n0.02 0.2 0.3\n"), l2,
                  {"ragged.txt:2", "3 columns", "same columns"});
  expect_rejected(write_text("col.txt", "0 0.1\n0.02 0.2\n"), layout_of("3", "g"),
                  {"col.txt:1", "column 3 does not exist", "valid: a column number 1..2"});
  expect_rejected(write_text("name.csv", "time,acc\n0,0.1\n0.02,0.2\n"), layout_of("ew", "g"),
                  {"name.csv:1", "no column named 'ew'", "'time', 'acc'", "header name"});
  expect_rejected(write_text("uneven.txt", "0 0.1\n0.02 0.2\n0.05 0.3\n0.06 0.1\n"), l2,
                  {"uneven.txt:", "off the uniform grid", "resample"});
  expect_rejected(write_text("back.txt", "0 0.1\n0.02 0.2\n0.02 0.3\n"), l2,
                  {"back.txt:3", "not after the previous sample", "times must increase"});
  expect_rejected(write_text("short.txt", "# only one\n0 0.1\n"), l2, {"short.txt", "at least two samples"});
  expect_rejected(write_text("same.txt", "0 0.1\n0.02 0.2\n"), layout_of("1", "g"),
                  {"same.txt:1", "acceleration column and the time column"});
}

TEST(GroundMotion, AccelerationUnits) {
  EXPECT_DOUBLE_EQ(parse_acceleration_unit("g").to_si, 9.80665);
  EXPECT_DOUBLE_EQ(parse_acceleration_unit("m/s^2").to_si, 1.0);
  EXPECT_DOUBLE_EQ(parse_acceleration_unit("9.81 m/s^2").to_si, 9.81);
  for (const char* bad : {"mm", "gal", "", "-1 g"}) {
    try {
      parse_acceleration_unit(bad);
      ADD_FAILURE() << "accepted unit '" << bad << "'";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("m/s2, g"), std::string::npos) << e.what();
    }
  }
}
