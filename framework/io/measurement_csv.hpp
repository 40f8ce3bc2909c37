#pragma once
// Single-joint shear test records in the measurement format of docs/measurement-format.md:
// '# key: value' metadata lines, a header naming the six required columns in any order (extra
// columns are kept), then one numeric row per sample. Laboratory records and rockdem results use
// the same format so that they can be compared line by line.
#include <string>
#include <utility>
#include <vector>

namespace rockdem {

struct MeasurementRow {
  double time_s;
  int stage;
  double normal_stress_MPa, shear_disp_mm, shear_stress_MPa, normal_disp_mm;
};

struct MeasurementFile {
  std::vector<std::pair<std::string, std::string>> metadata;  // in file order
  std::vector<MeasurementRow> rows;
  std::vector<std::string> extra_columns;  // names of the non-standard columns, in file order
  std::vector<std::vector<double>> extra;  // extra[i][j]: row i, extra column j
};

// Writes metadata lines, the header (six standard columns then the extra ones) and the rows.
// Values are written with enough digits to read back to within 1e-9 relative.
void write_measurement_csv(const std::string& path, const MeasurementFile& f);

// Reads and checks a file. Every broken rule (missing column, non-numeric value, NaN, time going
// backwards, wrong number of fields, stage not a positive integer) is an InputError naming the
// file, the line and the rule; nothing is silently dropped.
MeasurementFile read_measurement_csv(const std::string& path);

// A numeric CSV table with '# key: value' metadata lines before its header: the reader behind
// the measurement format, also used for drive tables (time_s, shear_disp_mm). Every row must have
// as many numeric, finite fields as the header; `required` columns must be in the header.
// Errors name the file, the line and the rule; `what` names the kind of file in messages.
struct CsvTable {
  std::vector<std::pair<std::string, std::string>> metadata;
  std::vector<std::string> columns;
  std::vector<std::vector<double>> rows;
  std::vector<int> lines;  // file line of each row
  int column(const std::string& name) const;  // index, -1 if absent
};
CsvTable read_csv_table(const std::string& path, const std::vector<std::string>& required, const std::string& what);

}  // namespace rockdem
