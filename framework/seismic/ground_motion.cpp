#include "framework/seismic/ground_motion.hpp"

#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "framework/core/error.hpp"
#include "framework/core/names.hpp"
#include "framework/core/units.hpp"

namespace rockdem::seismic {
namespace {

std::string_view trim(std::string_view s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
  return s;
}

std::vector<std::string_view> split(std::string_view line, bool csv) {
  std::vector<std::string_view> out;
  if (csv) {
    std::size_t start = 0;
    for (std::size_t i = 0; i <= line.size(); ++i) {
      if (i == line.size() || line[i] == ',') {
        out.push_back(trim(line.substr(start, i - start)));
        start = i + 1;
      }
    }
    return out;
  }
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && std::isspace(static_cast<unsigned char>(line[i]))) ++i;
    const std::size_t b = i;
    while (i < line.size() && !std::isspace(static_cast<unsigned char>(line[i]))) ++i;
    if (i > b) out.push_back(line.substr(b, i - b));
  }
  return out;
}

std::optional<double> to_number(std::string_view s) {
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  double v = 0.0;
  const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || ptr != s.data() + s.size() || s.empty()) return std::nullopt;
  return v;
}

}  // namespace

AccelerationUnit parse_acceleration_unit(std::string_view text) {
  const std::string_view t = trim(text);
  const bool has_number = !t.empty() && (std::isdigit(static_cast<unsigned char>(t.front())) || t.front() == '.');
  try {
    // A bare unit is the size of one such unit; a quantity is taken as written.
    const double v = parse_quantity(has_number ? std::string(t) : "1 " + std::string(t), Dimension::acceleration);
    if (!(v > 0.0) || !std::isfinite(v)) throw InputError("it must be positive");
    return {v, std::string(t)};
  } catch (const InputError& e) {
    throw InputError("acceleration unit '" + std::string(text) + "': " + e.what() + "; valid: a unit (" +
                     std::string(units_for(Dimension::acceleration)) +
                     ") or the size of one record unit as a quantity, e.g. \"9.81 m/s^2\"");
  }
}

std::size_t peak_index(const std::vector<double>& x) {
  std::size_t k = 0;
  for (std::size_t i = 1; i < x.size(); ++i)
    if (std::abs(x[i]) > std::abs(x[k])) k = i;
  return k;
}

namespace {

// Opens the record and checks the layout's time column before anything is read.
std::ifstream open_record(const std::string& path, const RecordLayout& layout) {
  std::ifstream in(path);
  if (!in) {
    throw InputError(path + ": cannot open the record (" +
                     (std::filesystem::exists(path) ? "not readable" : "no such file") + ")");
  }
  if (layout.time_column < 0) {
    throw InputError(path + ": time column " + std::to_string(layout.time_column) +
                     " is invalid; valid: 0 (no time column, give dt) or a column number from 1");
  }
  if (layout.time_column == 0 && !(layout.dt && *layout.dt > 0.0)) {
    throw InputError(path +
                     ": the record has no time column (time column 0), so a positive time step dt is "
                     "required");
  }
  return in;
}

// The record's columns as its header and first data line give them (indices 0-based).
struct RecordColumns {
  bool csv = false;
  std::vector<std::string> header;
  int header_line = 0;
  std::size_t ncols = 0, acc_col = 0;
};

// The acceleration column the layout names (a number, a header name, or the last column).
std::size_t acceleration_column(const std::string& path, const std::string& where, const RecordLayout& layout,
                                const RecordColumns& cols) {
  const std::string& c = layout.column;
  const std::string valid =
      "valid: a column number 1.." + std::to_string(cols.ncols) + (cols.header.empty() ? std::string() : " or a header name");
  if (c.empty()) return cols.ncols - 1;
  if (auto n = to_number(c); n && std::floor(*n) == *n) {
    if (*n < 1 || *n > static_cast<double>(cols.ncols)) {
      throw InputError(where + ": acceleration column " + c + " does not exist; the record has " +
                       std::to_string(cols.ncols) + " columns (" + valid + ")");
    }
    return static_cast<std::size_t>(*n) - 1;
  }
  std::size_t k = 0;
  while (k < cols.header.size() && cols.header[k] != c) ++k;
  if (k == cols.header.size()) {
    const std::string names = join_names(cols.header, [](const std::string& h) { return "'" + h + "'"; });
    throw InputError(path + (cols.header_line ? ":" + std::to_string(cols.header_line) : std::string()) +
                     ": no column named '" + c + "'" +
                     (cols.header.empty() ? " (the record has no header)" : " in the header (" + names + ")") + "; " +
                     valid);
  }
  return k;
}

// Fixes the record's width and its acceleration column from the first data line, once.
void resolve_columns(const std::string& path, const std::string& where, std::size_t nfields, const RecordLayout& layout,
                     RecordColumns& cols) {
  if (!cols.header.empty() && nfields != cols.header.size()) {
    throw InputError(where + ": " + std::to_string(nfields) + " columns, but the header on line " +
                     std::to_string(cols.header_line) + " names " + std::to_string(cols.header.size()) +
                     "; header and data lines must have the same columns");
  }
  cols.ncols = nfields;
  // Resolve the acceleration column once the width of the file is known.
  cols.acc_col = acceleration_column(path, where, layout, cols);
  if (layout.time_column > static_cast<int>(cols.ncols)) {
    throw InputError(where + ": time column " + std::to_string(layout.time_column) +
                     " does not exist; the record has " + std::to_string(cols.ncols) +
                     " columns (valid: 0 for none, or 1.." + std::to_string(cols.ncols) + ")");
  }
  if (layout.time_column > 0 && static_cast<std::size_t>(layout.time_column - 1) == cols.acc_col) {
    throw InputError(where + ": the acceleration column and the time column are both column " +
                     std::to_string(cols.acc_col + 1) +
                     "; choose another acceleration column (or time column 0 and a time step dt for a "
                     "record without times)");
  }
}

// The samples read: times (if the record has them), accelerations [m/s^2], and each sample's line.
struct Samples {
  std::vector<double> tt, aa;
  std::vector<int> line_of;
};

// One data line's time and acceleration, appended to `samples`.
void read_data_line(const std::vector<std::string_view>& fields, const std::string& where, const RecordLayout& layout,
                    const RecordColumns& cols, Samples& samples) {
  if (fields.size() != cols.ncols) {
    throw InputError(where + ": " + std::to_string(fields.size()) +
                     " columns, but the record's first data line has " + std::to_string(cols.ncols) +
                     "; every data line must have the same columns");
  }
  for (std::size_t k = 0; k < fields.size(); ++k) {
    const bool used =
        k == cols.acc_col || (layout.time_column > 0 && k == static_cast<std::size_t>(layout.time_column - 1));
    if (!used) continue;
    const auto v = to_number(fields[k]);
    if (!v || !std::isfinite(*v)) {
      throw InputError(where + ": column " + std::to_string(k + 1) + " holds '" + std::string(fields[k]) +
                       "', which is not a finite number; data lines hold numbers only (one header line "
                       "is allowed before them, comment lines start with #)");
    }
    if (k == cols.acc_col)
      samples.aa.push_back(*v * layout.unit.to_si);
    else
      samples.tt.push_back(*v);
  }
}

// Reads the record's lines: comments skipped, an optional header, then data lines.
Samples read_samples(std::istream& in, const std::string& path, const RecordLayout& layout, RecordColumns& cols) {
  Samples samples;
  std::string line;
  int ln = 0;
  bool first = true, resolved = false;
  const std::string where_prefix = path + ":";
  while (std::getline(in, line)) {
    ++ln;
    std::string_view s = trim(line);
    if (s.empty() || s.front() == '#') continue;
    const std::string where = where_prefix + std::to_string(ln);
    if (first) {
      cols.csv = cols.csv || s.find(',') != std::string_view::npos;
      auto fields = split(s, cols.csv);
      if (!to_number(fields.front())) {  // a header line
        for (auto f : fields) cols.header.emplace_back(f);
        cols.header_line = ln;
        first = false;
        continue;
      }
    }
    auto fields = split(s, cols.csv);
    first = false;
    if (!resolved) {
      resolved = true;
      resolve_columns(path, where, fields.size(), layout, cols);
    }
    read_data_line(fields, where, layout, cols, samples);
    samples.line_of.push_back(ln);
  }
  return samples;
}

// Sets the record's t0 and dt from its times, which must increase on a uniform grid.
void set_sampling_from_times(const Samples& samples, const std::string& path, GroundMotion& g) {
  const std::vector<double>& tt = samples.tt;
  const std::string where_prefix = path + ":";
  for (std::size_t i = 1; i < tt.size(); ++i) {
    if (!(tt[i] > tt[i - 1])) {
      throw InputError(where_prefix + std::to_string(samples.line_of[i]) + ": time " +
                       format_quantity(tt[i], Dimension::time) + " is not after the previous sample's " +
                       format_quantity(tt[i - 1], Dimension::time) + "; times must increase");
    }
  }
  g.t0 = tt.front();
  g.dt = (tt.back() - tt.front()) / static_cast<double>(tt.size() - 1);
  // Printed times carry rounding (163.39999), so each sample may stray from the grid by 1e-3 dt.
  for (std::size_t i = 0; i < tt.size(); ++i) {
    const double grid = g.t0 + g.dt * static_cast<double>(i);
    if (std::abs(tt[i] - grid) > 1e-3 * g.dt) {
      throw InputError(
          where_prefix + std::to_string(samples.line_of[i]) + ": time " + format_quantity(tt[i], Dimension::time) +
          " is off the uniform grid t0 + i*dt = " + format_quantity(grid, Dimension::time) +
          " (t0 = " + format_quantity(g.t0, Dimension::time) + ", dt = " + format_quantity(g.dt, Dimension::time) +
          " from the first and last samples); a record must be "
          "sampled uniformly (to 1e-3 dt): resample it first");
    }
  }
}

}  // namespace

GroundMotion load_ground_motion(const std::string& path, const RecordLayout& layout) {
  std::ifstream in = open_record(path, layout);
  RecordColumns cols;
  cols.csv = std::filesystem::path(path).extension() == ".csv";
  Samples samples = read_samples(in, path, layout, cols);
  if (samples.aa.size() < 2) {
    throw InputError(path + ": " + std::to_string(samples.aa.size()) + " data line(s); a record needs at least two samples");
  }
  GroundMotion g;
  g.source = path;
  g.column_name = cols.header.empty() ? "column " + std::to_string(cols.acc_col + 1) : cols.header[cols.acc_col];
  if (layout.time_column == 0) {
    g.t0 = 0.0;
    g.dt = *layout.dt;
  } else {
    set_sampling_from_times(samples, path, g);
  }
  g.acc = std::move(samples.aa);
  return g;
}

}  // namespace rockdem::seismic
