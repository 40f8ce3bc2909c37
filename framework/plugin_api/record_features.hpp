#pragma once
// What a measured shear record shows, in terms a law or effect can judge without seeing the
// record: plug-ins (models/) sit below the analysis layer that reads and segments records, so
// analysis fills this in (record_features in framework/analysis/diagnosis.hpp) and an effect's
// optional `unjudgeable` hook (framework/plugin_api/effect.hpp) says from it whether the record
// can reveal the effect at all.
#include <cstddef>
#include <string>
#include <vector>

namespace rockdem {

struct RecordFeatures {
  std::size_t reverse_rows = 0;        // rows sheared back toward the mated position
  std::size_t negative_side_rows = 0;  // rows on the negative side of the mated position
  std::size_t positive_side_rows = 0;  // rows on the positive side
  int cycles = 0;                      // shear cycles (strokes), summed over the stages
  // 10th and 90th percentiles of the shear rate over the rows that move [mm/s]; both 0 when
  // no row moves. A constant-rate test has them close together.
  double rate_low = 0.0, rate_high = 0.0;
  // Holds: stretches in which the joint is held still and then sheared again (slide-hold-slide
  // tests, pauses between episodes). Time-dependent strengthening (healing) shows on the slide
  // after a hold even when every slide runs at the same rate.
  int holds = 0;              // holds followed by shearing, of at least 1 s
  double longest_hold_s = 0;  // the longest of them [s]
  struct Stage {
    double normal_stress_MPa = 0.0;  // the stage's nominal (median) normal stress
    double min_normal_stress_MPa = 0.0, max_normal_stress_MPa = 0.0;  // over its rows
  };
  std::vector<Stage> stages;
};

// Shared by the effects that act only when the joint is sheared back toward the mated position:
// a few rows of reverse shearing are needed before their fit means anything.
inline std::string reason_without_reverse_shearing(const RecordFeatures& f) {
  if (f.reverse_rows < 5) return "no reverse shearing toward the mated position in the record";
  return {};
}

}  // namespace rockdem
