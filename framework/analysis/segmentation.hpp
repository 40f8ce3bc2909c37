#pragma once
// Splits a single-joint shear record (the measurement format, docs/measurement-format.md)
// into stages and monotonic segments of shear displacement, and labels every row with its stage,
// cycle, quadrant and shearing direction as the format document defines them:
//   cycle     one excursion 0 -> +max -> 0 -> -max -> 0 (or 0 -> +max -> 0, one-sided);
//   quadrant  1: moving away on the positive side, 4: returning from the positive side,
//             3: moving away on the negative side, 2: returning from the negative side;
//   forward / reverse: moving away from / back toward the mated position (u = 0).
// Reversals are found with a hysteresis threshold (a fraction of the stage's displacement range),
// so noise and chatter smaller than it never start a segment. Comparison, calibration and
// diagnosis all work on these labels; covariates a later analysis needs go into RowLabel.
#include <cstddef>
#include <map>
#include <string>
#include <vector>

#include "framework/io/measurement_csv.hpp"

namespace rockdem {

struct SegmentationOptions {
  // A reversal counts once the displacement has come back by more than this fraction of the
  // stage's range (max - min of shear_disp_mm): larger than noise, smaller than a real stroke.
  double reversal_fraction = 0.02;
  // Per-stage threshold [mm] overriding reversal_fraction (compare segments a model with the
  // measurement's thresholds, so that the two are cut by the same rule).
  std::map<int, double> threshold_mm;
};

// Labels of one row.
struct RowLabel {
  int stage = 0;      // stage number as written in the file
  int segment = 0;    // monotonic segment, 0-based within the stage
  int cycle = 0;      // 1-based within the stage
  int quadrant = 0;   // 1..4 as above; 0: no shear motion in this stage (e.g. normal loading only)
  int direction = 0;  // +1 forward (away from u = 0), -1 reverse (toward it), 0 none
  int motion = 0;     // +1 shear displacement increasing, -1 decreasing, 0 none
};

// A monotonic run of shear displacement between two reversals (turning points).
struct Segment {
  int stage = 0;
  int index = 0;                  // 0-based within the stage
  int motion = 0;                 // +1 increasing, -1 decreasing, 0 no motion beyond the threshold
  std::size_t begin = 0, end = 0; // rows [begin, end) labelled with this segment
  // First row of the segment's curve: the turning point that ends the previous segment (or the
  // stage's first row), so that the curve is continuous from one segment to the next.
  std::size_t curve_begin = 0;
  double u_start = 0.0, u_end = 0.0;  // shear displacement at curve_begin and at end - 1 [mm]
};

struct StageInfo {
  int stage = 0;
  std::size_t begin = 0, end = 0;      // rows [begin, end)
  std::size_t first_segment = 0, segment_count = 0;  // into Segmentation::segments
  double u_min = 0.0, u_max = 0.0;     // [mm]
  double threshold = 0.0;              // reversal threshold used [mm]
  int first_side = 0;                  // sign of the first stroke (+1/-1; 0 if no motion)
  int cycles = 0;
  double normal_stress_MPa = 0.0;      // median over the stage's rows
};

struct Segmentation {
  std::vector<StageInfo> stages;   // in file order
  std::vector<Segment> segments;   // all stages, in file order
  std::vector<RowLabel> labels;    // one per row of the file

  const StageInfo* find_stage(int stage) const;
};

// A stage's normal stress as segment() gives it (StageInfo::normal_stress_MPa): the median of
// rows [begin, end).
double stage_normal_stress(const MeasurementFile& f, std::size_t begin, std::size_t end);

// Segments `f`. Never throws on a well-formed file (read_measurement_csv's rules).
Segmentation segment(const MeasurementFile& f, const SegmentationOptions& options = {});

// Turning points of shear displacement in rows [begin, end) by hysteresis: a reversal counts once
// the displacement has come back by more than `threshold` [mm] from the running extreme. Writes the
// turning rows in order into `turns` and the first stroke's direction (+1/-1, 0 if none) into
// `first_motion`. segment() cuts stages with it; compare also cuts segments finer with it.
void find_reversals(const MeasurementFile& f, std::size_t begin, std::size_t end, double threshold,
                    std::vector<std::size_t>& turns, int& first_motion);

// "forward shearing (quadrant 1)", "reverse shearing (quadrant 4)", ... for reports.
std::string quadrant_phrase(int quadrant);

}  // namespace rockdem
