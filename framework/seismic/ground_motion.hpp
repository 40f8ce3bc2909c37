#pragma once
// Loading of strong-motion accelerograms (text columns or CSV) into SI acceleration, with the
// checks that catch the usual mistakes: wrong column, wrong unit, irregular sampling. Every
// problem is an InputError naming file:line, what is wrong and what is valid.
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace rockdem::seismic {

// The size of one unit of the record's values, in m/s^2. Written as a unit ("g", "m/s^2") or as
// a quantity ("9.81 m/s^2" for records whose g was rounded).
struct AccelerationUnit {
  double to_si = 1.0;
  std::string text;  // as the user wrote it, for metadata
};
// Throws InputError (without location; the caller adds it) naming the valid units.
AccelerationUnit parse_acceleration_unit(std::string_view text);

struct RecordLayout {
  // 1-based column of the acceleration; for CSV also a header name. Empty: the last column.
  std::string column;
  // 1-based column of time; 0: the file has none and `dt` gives the sampling.
  int time_column = 1;
  std::optional<double> dt;  // s; required when time_column == 0
  AccelerationUnit unit;
};

struct GroundMotion {
  std::string source;       // file as given
  std::string column_name;  // header name or "column N"
  double t0 = 0.0;          // s, time of the first sample
  double dt = 0.0;          // s, uniform
  std::vector<double> acc;  // m/s^2
  double duration() const { return acc.empty() ? 0.0 : dt * static_cast<double>(acc.size() - 1); }
};

// Whitespace-separated columns, or comma-separated (CSV: files ending in .csv or whose first
// data line has commas). Lines starting with '#' and a non-numeric first line (a header) are
// skipped. Sampling must be uniform to 1e-3 dt; at least two samples.
GroundMotion load_ground_motion(const std::string& path, const RecordLayout& layout);

// A record in the PEER NGA format (.AT2): four header lines (the third names the unit, "UNITS
// OF G"; the fourth gives NPTS and DT, as "NPTS= n, DT= dt SEC" or "n dt NPTS, DT"), then the
// NPTS accelerations, several per line. Every problem is an InputError naming file:line.
GroundMotion load_peer_at2(const std::string& path);

// Index of the largest |acc|.
std::size_t peak_index(const std::vector<double>& x);

}  // namespace rockdem::seismic
