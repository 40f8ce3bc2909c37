// Test 24's shear displacement drive (cases/direct_shear/data/test24_drive.csv): re-made here from
// the committed Mexico 1985 SCT record with the processing of scripts/make-test24-drive, it must
// have the report's 25.4 mm peak and ~0.5 Hz dominant frequency, end near rest, and equal the
// committed file (so the file cannot drift from the code that documents it).
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "framework/seismic/ground_motion.hpp"
#include "framework/seismic/signal_processing.hpp"

using namespace rockdem::seismic;

namespace {

// The options of scripts/make-test24-drive, written out (the file's "# processing:" line is
// compared with them below, so a change on either side shows).
DisplacementProcessing test24_processing() {
  DisplacementProcessing p;
  p.start = 40.0;
  p.end = 80.0;
  p.acc_baseline_degree = 1;
  p.taper = 3.0;
  p.pad = 10.0;
  p.f_low = 0.2;
  p.f_high = 2.0;
  p.order = 2;
  p.disp_baseline_degree = 3;
  p.peak_displacement = 0.0254;
  return p;
}

ProcessedMotion make_drive() {
  RecordLayout layout;
  layout.column = "3";  // E-W
  layout.unit = parse_acceleration_unit("g");
  const auto g = load_ground_motion(ROCKDEM_SOURCE_DIR "/cases/data/ground_motions/mexico1985_sct_acc_g.txt", layout);
  return process_to_displacement(g, test24_processing());
}

}  // namespace

TEST(Test24Drive, PeakEndAndDominantFrequency) {
  const auto m = make_drive();
  EXPECT_LE(m.dt, 0.02 + 1e-12);  // the element driver and DEM read it at this sampling or coarser
  const double peak = peak_abs(m.disp);
  EXPECT_NEAR(peak, 0.0254, 0.001 * 0.0254);
  EXPECT_LT(std::abs(m.disp.back()), 0.02 * peak);
  EXPECT_DOUBLE_EQ(m.disp.front(), 0.0);
  const double f = dominant_frequency(m.disp, m.dt);
  EXPECT_GE(f, 0.4);
  EXPECT_LE(f, 0.6);
  // The shaking fills the window: tens of seconds above 10 % of the peak, not a single pulse.
  std::size_t first = m.disp.size(), last = 0;
  for (std::size_t i = 0; i < m.disp.size(); ++i) {
    if (std::abs(m.disp[i]) > 0.1 * peak) {
      first = std::min(first, i);
      last = i;
    }
  }
  EXPECT_GT(m.dt * static_cast<double>(last - first), 30.0);
}

TEST(Test24Drive, CommittedFileMatchesTheProcessing) {
  const auto m = make_drive();
  const std::string path = ROCKDEM_SOURCE_DIR "/cases/direct_shear/data/test24_drive.csv";
  std::ifstream in(path);
  ASSERT_TRUE(in) << path;
  std::string line, processing, source;
  bool header = false;
  std::vector<double> t, u;
  while (std::getline(in, line)) {
    if (line.rfind("# processing: ", 0) == 0) processing = line.substr(14);
    if (line.rfind("# source: ", 0) == 0) source = line.substr(10);
    if (line.empty() || line[0] == '#') continue;
    if (!header) {
      EXPECT_EQ(line, "time_s,shear_disp_mm");
      header = true;
      continue;
    }
    std::istringstream is(line);
    double a = 0, b = 0;
    char comma = 0;
    is >> a >> comma >> b;
    ASSERT_TRUE(is && comma == ',') << line;
    t.push_back(a);
    u.push_back(b);
  }
  EXPECT_EQ(processing, test24_processing().describe());
  EXPECT_EQ(source, "cases/data/ground_motions/mexico1985_sct_acc_g.txt");
  ASSERT_EQ(u.size(), m.disp.size());
  for (std::size_t i = 0; i < u.size(); ++i) {
    ASSERT_NEAR(t[i], m.time[i], 5e-4) << "row " << i;
    ASSERT_NEAR(u[i], m.disp[i] * 1e3, 6e-5) << "row " << i;  // written with 4 decimals in mm
  }
}
