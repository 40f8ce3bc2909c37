#pragma once
// Model against measurement for single-joint shear records. The two are aligned on shear
// displacement, not time (the DEM and the laboratory run at different rates): each measured row
// is matched to the model's value at the same shear displacement within the same stage and the
// same monotonic segment (first passage, linear interpolation; within a segment, between the
// finer reversals both records share). Errors are then summarised per
// variable (shear stress [MPa], normal displacement [mm]) overall, per stage, per cycle, per
// quadrant and per stage x cycle x quadrant:
//   RMSE, NRMSE = RMSE / (max - min of the measured variable over the whole file),
//   bias = mean(model - measurement), magnitude bias = mean(|model| - |measurement|);
//   combined NRMSE = mean of the two variables' NRMSE.
// Records whose stages or shear paths differ are refused (InputError saying what differs).
#include <array>
#include <cstddef>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "framework/analysis/segmentation.hpp"
#include "framework/io/measurement_csv.hpp"

namespace rockdem {

// The compared variables, in this order everywhere (index 0, 1).
struct CompareVariable {
  const char* key;   // JSON key
  const char* name;  // plain words
  const char* unit;
};
inline constexpr std::array<CompareVariable, 2> kCompareVariables{
    {{"shear_stress", "shear stress", "MPa"}, {"normal_disp", "normal displacement", "mm"}}};
double compared_value(const MeasurementRow& r, std::size_t variable);

struct CompareOptions {
  // Reversal threshold of the measurement's segmentation; the model is cut with the
  // measurement's per-stage thresholds so that identical paths give identical segments.
  SegmentationOptions segmentation;
  // Extremes and turning points may differ by this fraction of the stage's amplitude (max |u|):
  // a compliant loading frame makes a measured stroke a few per cent shorter than the command.
  double endpoint_tolerance = 0.10;
  // Within a segment, reversals larger than this fraction of the segment threshold (or twice,
  // four times ... up to half of it) are matched between the records when both show the same
  // number; alignment then runs piece by piece. 0: whole segments only.
  double fine_fraction = 0.05;
  // Stage normal stresses (medians) may differ by this fraction (+ 0.01 MPa).
  double normal_stress_tolerance = 0.10;
  int worst_lines = 3;            // plain-language lines for the worst segments
  std::size_t worst_min_rows = 3; // segments with fewer measured rows are not ranked
};

struct ErrorStats {
  std::size_t n = 0;
  double rmse = 0.0, nrmse = 0.0, bias = 0.0;
  // mean(|model| - |measured|): for shear stress, whose sign is the shearing direction, the
  // over/under-prediction of strength whichever way the joint is sheared.
  double magnitude_bias = 0.0;
  double mean_abs_measured = 0.0;  // mean |measured value|, the reference of percentages
};

// A group of measured rows; 0 in stage, cycle or quadrant means "all".
struct ErrorGroup {
  int stage = 0, cycle = 0, quadrant = 0;
  std::array<ErrorStats, 2> var{};
};

// Where a measured row sits on the model record: between model rows j0 and j1 at the fraction t
// (t = 1: row j1's sample as it is); j0 = kNone where no segment covers the row (NaN).
struct AlignedRow {
  static constexpr std::size_t kNone = static_cast<std::size_t>(-1);
  std::size_t j0 = kNone, j1 = kNone;
  double t = 0.0;
};

// The model's compared variable v (0 shear stress, 1 normal displacement) at a placed row.
double aligned_value(const AlignedRow& a, const MeasurementFile& model, std::size_t v);

// The model's values interpolated at every measured row.
struct Alignment {
  std::array<std::vector<double>, 2> model;
  // Where each measured row was placed. It depends on the model record's stages, shear
  // displacement, normal stress and time only (what segment() and align() read besides the
  // compared values), so a model run along the same path can reuse it (calibration does).
  std::vector<AlignedRow> rows;
  // Measured rows beyond the ends of the model's matching segment (the model's end value is
  // used); within the end-point tolerance these are expected, a large count is worth a look.
  std::size_t outside = 0;
  std::size_t finely_aligned_segments = 0;  // segments aligned piece by piece between finer reversals
};

struct Comparison {
  Segmentation data_segments, model_segments;
  Alignment alignment;
  std::array<double, 2> range{};  // of the measured variables over the whole file
  ErrorGroup overall;
  std::vector<ErrorGroup> stages, cycles, quadrants, segments;  // segments: stage x cycle x quadrant
  double combined_nrmse = 0.0;
  std::vector<std::string> worst;  // plain-language lines, worst first
  std::vector<std::string> notes;  // how the comparison departed from the defaults (raised thresholds)
};

// Model segmentation options matching a measurement's segmentation (same thresholds).
SegmentationOptions model_segmentation_options(const Segmentation& data);

// Throws InputError (without file names: callers add them) if the stage lists, normal stresses,
// first-stroke signs, extremes, number of reversals or turning points differ. compare() first
// tries coarser reversal thresholds where only the reversals differ (Comparison::notes says so).
void check_compatible(const Segmentation& data, const Segmentation& model, const CompareOptions& options = {});

// compare()'s check of a stage's normal stress: the model's (StageInfo::normal_stress_MPa) against
// the measurement's, within options.normal_stress_tolerance; the reason if they differ, else "".
std::string normal_stress_mismatch(const StageInfo& data, double model_MPa, const CompareOptions& options = {});
// The same for every stage of a model record whose stages are `model_stages` (its segmentation's,
// in the measurement's order): the first reason, else "". Calibration, reusing an alignment,
// checks only this again.
std::string normal_stress_mismatch(const Segmentation& data, const MeasurementFile& model,
                                   const std::vector<StageInfo>& model_stages, const CompareOptions& options = {});

// Interpolates the model at every measured row; the segmentations must be compatible.
Alignment align(const MeasurementFile& data, const Segmentation& data_segments, const MeasurementFile& model,
                const Segmentation& model_segments, const CompareOptions& options = {});

// Error groups, combined NRMSE and worst lines from an alignment (fills every field of the
// result but the two segmentations and the alignment).
void summarize(const MeasurementFile& data, const Segmentation& data_segments, const Alignment& alignment,
               const CompareOptions& options, Comparison& out);

// The segmentations (thresholds raised where only the reversals differ, as notes say) and the
// alignment, without the error groups: compare() less summarize(). Throws as compare() does.
Comparison align_records(const MeasurementFile& data, const Segmentation& data_segments, const MeasurementFile& model,
                         const CompareOptions& options = {});

// All of the above. The overload with a precomputed data segmentation serves repeated
// comparisons against one measurement (calibration).
Comparison compare(const MeasurementFile& data, const MeasurementFile& model, const CompareOptions& options = {});
Comparison compare(const MeasurementFile& data, const Segmentation& data_segments, const MeasurementFile& model,
                   const CompareOptions& options = {});

// JSON: nrmse {shear_stress, normal_disp, combined}, overall, stages, cycles, quadrants,
// segments (flat: one entry per variable and stage x cycle x quadrant), worst, alignment.
nlohmann::json to_json(const Comparison& c);
// Compact table for a terminal.
std::string format_table(const Comparison& c);

}  // namespace rockdem
