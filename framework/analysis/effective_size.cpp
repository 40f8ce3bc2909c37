#include "framework/analysis/effective_size.hpp"

#include <algorithm>
#include <cmath>

namespace rockdem {

EffectiveSize effective_sample_size(const MeasurementFile& data, const Segmentation& seg, const Comparison& c) {
  EffectiveSize out;
  const std::size_t rows = data.rows.size();
  for (std::size_t v = 0; v < 2; ++v) {
    // The same residuals the fit sums (Evaluator::residuals): every row of a variable with a range.
    if (!(c.range[v] > 0.0) || c.alignment.model[v].size() != rows || rows == 0) continue;
    double sum_sq = 0.0, lag = 0.0, prev = 0.0;
    for (std::size_t i = 0; i < rows; ++i) {
      double e = (c.alignment.model[v][i] - compared_value(data.rows[i], v)) / c.range[v];
      if (!std::isfinite(e)) e = 10.0;  // as the fit counts it
      sum_sq += e * e;
      if (i > 0 && seg.labels[i].stage == seg.labels[i - 1].stage) lag += e * prev;
      prev = e;
    }
    const double r1 = sum_sq > 0.0 ? std::clamp(lag / sum_sq, 0.0, 1.0 - 1e-12) : 0.0;
    const double n = static_cast<double>(rows);
    out.n[v] = rows;
    out.rss[v] = sum_sq;
    out.r1[v] = r1;
    out.n_eff[v] = std::min(n, std::max(n * (1.0 - r1) / (1.0 + r1), std::min(n, 5.0)));
  }
  return out;
}

}  // namespace rockdem
