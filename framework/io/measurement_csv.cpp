// Reader and writer of the single-joint measurement CSV (docs/measurement-format.md).
// The reader is strict on purpose: a laboratory record with a silently skipped row would bias a
// calibration without anybody noticing, so every rule violation stops with file, line and rule.
#include "framework/io/measurement_csv.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <string_view>

#include "framework/core/error.hpp"
#include "framework/io/output_folder.hpp"

namespace rockdem {
namespace {

constexpr std::array<std::string_view, 6> kColumns{"time_s",          "stage",
                                                   "normal_stress_MPa", "shear_disp_mm",
                                                   "shear_stress_MPa",  "normal_disp_mm"};

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t' || s.front() == '\r')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) s.remove_suffix(1);
  return s;
}

void split(std::string_view line, std::vector<std::string_view>& out) {
  out.clear();
  std::size_t start = 0;
  for (;;) {
    const std::size_t comma = line.find(',', start);
    out.push_back(trim(line.substr(start, comma == std::string_view::npos ? std::string_view::npos
                                                                          : comma - start)));
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
}

void append_number(std::string& out, double v) {
  std::array<char, 64> buf{};
  auto [end, ec] = std::to_chars(buf.data(), buf.data() + buf.size(), v);  // shortest round-trip
  (void)ec;
  out.append(buf.data(), end);
}

}  // namespace

void write_measurement_csv(const std::string& path, const MeasurementFile& f) {
  // A record with nan or inf in it reads as data to every tool after this one; refuse it here,
  // for every command that writes one, and say where the first bad value is.
  for (std::size_t i = 0; i < f.rows.size(); ++i) {
    const MeasurementRow& r = f.rows[i];
    const std::array<std::pair<const char*, double>, 5> v{{{"time_s", r.time_s}, {"normal_stress_MPa", r.normal_stress_MPa},
        {"shear_disp_mm", r.shear_disp_mm}, {"shear_stress_MPa", r.shear_stress_MPa}, {"normal_disp_mm", r.normal_disp_mm}}};
    for (const auto& [name, x] : v)
      if (!std::isfinite(x))
        throw InputError(path + ": not written: row " + std::to_string(i + 1) + " has " + name + " = " + std::to_string(x) +
                         " (a stiffness, amplitude or drive value in the input overflows); valid: inputs whose results stay finite");
  }
  // A row with fewer values than the header would make a file the reader rejects: refuse early.
  if (!f.extra_columns.empty() && f.extra.size() != f.rows.size()) {
    throw InputError(path + ": " + std::to_string(f.rows.size()) + " rows but " + std::to_string(f.extra.size()) +
                     " rows of extra-column values; nothing written");
  }
  for (std::size_t i = 0; i < f.extra.size() && !f.extra_columns.empty(); ++i) {
    if (f.extra[i].size() != f.extra_columns.size()) {
      throw InputError(path + ": row " + std::to_string(i + 1) + " has " + std::to_string(f.extra[i].size()) +
                       " extra values for " + std::to_string(f.extra_columns.size()) + " extra columns; nothing written");
    }
  }
  std::string out;
  out.reserve(64 + f.rows.size() * (64 + 16 * f.extra_columns.size()));
  for (const auto& [k, v] : f.metadata) {
    out += "# ";
    out += k;
    out += ": ";
    out += v;
    out += '\n';
  }
  for (std::size_t i = 0; i < kColumns.size(); ++i) {
    if (i) out += ',';
    out += kColumns[i];
  }
  for (const auto& c : f.extra_columns) {
    out += ',';
    out += c;
  }
  out += '\n';
  for (std::size_t i = 0; i < f.rows.size(); ++i) {
    const auto& r = f.rows[i];
    append_number(out, r.time_s);
    out += ',';
    out += std::to_string(r.stage);
    out += ',';
    append_number(out, r.normal_stress_MPa);
    out += ',';
    append_number(out, r.shear_disp_mm);
    out += ',';
    append_number(out, r.shear_stress_MPa);
    out += ',';
    append_number(out, r.normal_disp_mm);
    if (i < f.extra.size()) {
      for (double v : f.extra[i]) {
        out += ',';
        append_number(out, v);
      }
    }
    out += '\n';
  }
  // Through a temporary file and a rename: a full disk or a kill leaves the old file or none,
  // never a truncated record that reads as a shorter test.
  write_file_atomically(path, out);
}

CsvTable read_csv_table(const std::string& path, const std::vector<std::string>& required, const std::string& what) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot open " + what + " (missing or unreadable)");
  CsvTable f;
  std::string line;
  int lineno = 0;
  bool have_header = false;
  std::vector<std::string_view> fields;
  auto fail = [&](const std::string& rule) -> InputError {
    return InputError(path + ":" + std::to_string(lineno) + ": " + rule);
  };
  while (std::getline(in, line)) {
    ++lineno;
    const std::string_view s = trim(line);
    if (s.empty()) continue;  // blank lines carry no data
    if (s.front() == '#') {
      if (have_header) throw fail("comment/metadata line after the header; '# key: value' lines must precede it");
      const std::string_view body = trim(s.substr(1));
      const std::size_t colon = body.find(':');
      if (colon == std::string_view::npos) {
        f.metadata.emplace_back(std::string(body), std::string());
      } else {
        f.metadata.emplace_back(std::string(trim(body.substr(0, colon))),
                                std::string(trim(body.substr(colon + 1))));
      }
      continue;
    }
    split(s, fields);
    if (!have_header) {
      for (const auto& name : fields) {
        if (name.empty()) throw fail("empty column name in the header");
        if (f.column(std::string(name)) >= 0) throw fail("column '" + std::string(name) + "' appears twice in the header");
        f.columns.emplace_back(name);
      }
      for (const auto& r : required) {
        if (f.column(r) < 0) {
          std::string all;
          for (const auto& k : required) all += (all.empty() ? "" : ",") + k;
          throw fail("missing column '" + r + "' in the header; required columns: " + all);
        }
      }
      have_header = true;
      continue;
    }
    if (fields.size() != f.columns.size()) {
      throw fail("row has " + std::to_string(fields.size()) + " fields, the header has " +
                 std::to_string(f.columns.size()));
    }
    std::vector<double> values(fields.size());
    for (std::size_t i = 0; i < fields.size(); ++i) {
      const std::string_view v = fields[i];
      double x = 0.0;
      const char* b = v.data();
      const char* e = v.data() + v.size();
      if (!v.empty() && *b == '+') ++b;  // from_chars rejects a leading '+'
      auto [ptr, ec] = std::from_chars(b, e, x);
      if (v.empty() || ec != std::errc() || ptr != e) {
        throw fail("non-numeric value '" + std::string(v) + "' in column '" + f.columns[i] + "'");
      }
      if (std::isnan(x)) throw fail("NaN in column '" + f.columns[i] + "'; every value must be a number");
      if (!std::isfinite(x)) throw fail("infinite value in column '" + f.columns[i] + "'");
      values[i] = x;
    }
    f.rows.push_back(std::move(values));
    f.lines.push_back(lineno);
  }
  if (!have_header) {
    std::string all;
    for (const auto& k : required) all += (all.empty() ? "" : ",") + k;
    throw InputError(path + ":" + std::to_string(lineno) + ": no header line found; the header names the columns " + all);
  }
  return f;
}

int CsvTable::column(const std::string& name) const {
  for (std::size_t i = 0; i < columns.size(); ++i)
    if (columns[i] == name) return static_cast<int>(i);
  return -1;
}

MeasurementFile read_measurement_csv(const std::string& path) {
  const CsvTable t = read_csv_table(path, std::vector<std::string>(kColumns.begin(), kColumns.end()), "measurement file");
  MeasurementFile f;
  f.metadata = t.metadata;
  // Metadata the tools read as numbers is checked here, once, so that a bad value is named with
  // its file instead of surfacing later as a bare "stod" from whichever tool reads it.
  for (const auto& [key, value] : f.metadata) {
    if (key != "joint_length_m") continue;
    double v = 0.0;
    const auto [ptr, ec] = std::from_chars(value.data(), value.data() + value.size(), v);
    if (ec != std::errc() || ptr != value.data() + value.size() || !std::isfinite(v) || !(v > 0.0))
      throw InputError(path + ": metadata '# " + key + ": " + value + "' must be a positive number of metres, e.g. '# " +
                       key + ": 0.1'");
  }
  std::array<std::size_t, 6> col{};
  for (std::size_t c = 0; c < kColumns.size(); ++c) col[c] = static_cast<std::size_t>(t.column(std::string(kColumns[c])));
  std::vector<std::size_t> extra_pos;
  for (std::size_t i = 0; i < t.columns.size(); ++i)
    if (std::find(kColumns.begin(), kColumns.end(), t.columns[i]) == kColumns.end()) {
      extra_pos.push_back(i);
      f.extra_columns.push_back(t.columns[i]);
    }
  double last_time = -std::numeric_limits<double>::infinity();
  int last_stage = 0;
  f.rows.reserve(t.rows.size());
  f.extra.reserve(t.rows.size());
  for (std::size_t k = 0; k < t.rows.size(); ++k) {
    const auto& values = t.rows[k];
    auto fail = [&](const std::string& rule) -> InputError {
      return InputError(path + ":" + std::to_string(t.lines[k]) + ": " + rule);
    };
    MeasurementRow r{};
    r.time_s = values[col[0]];
    const double stage = values[col[1]];
    r.normal_stress_MPa = values[col[2]];
    r.shear_disp_mm = values[col[3]];
    r.shear_stress_MPa = values[col[4]];
    r.normal_disp_mm = values[col[5]];
    if (stage != std::floor(stage) || stage < 1.0 || stage > 1e6) {
      throw fail("stage must be a positive integer (1, 2, ...), found " + std::to_string(stage));
    }
    r.stage = static_cast<int>(stage);
    if (r.time_s < last_time) {
      throw fail("time going backwards: time_s = " + std::to_string(r.time_s) + " after " + std::to_string(last_time) +
                 "; time_s must be non-decreasing over the whole file");
    }
    if (r.stage < last_stage) {
      throw fail("stage " + std::to_string(r.stage) + " after stage " + std::to_string(last_stage) +
                 "; stages are numbered in test order and must not decrease");
    }
    last_time = r.time_s;
    last_stage = r.stage;
    f.rows.push_back(r);
    std::vector<double> ex(extra_pos.size());
    for (std::size_t j = 0; j < extra_pos.size(); ++j) ex[j] = values[extra_pos[j]];
    f.extra.push_back(std::move(ex));
  }
  return f;
}

}  // namespace rockdem
