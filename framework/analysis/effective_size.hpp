#pragma once
// How many independent values a fit's residuals are worth (diagnose's information criterion,
// calibrate's profile-likelihood intervals).
#include <array>
#include <cstddef>

#include "framework/analysis/compare.hpp"
#include "framework/analysis/segmentation.hpp"

namespace rockdem {

// A fit's residuals per variable (shear stress, normal displacement; range-normalised, every row
// as the fit counts them) and how many independent values they are worth. Residuals of
// neighbouring rows are strongly correlated where a model misses a shape (one systematic misfit
// spans hundreds of rows), and a criterion that counts rows credits an effect for bending a little
// of that one misfit once per row. AR(1) approximation: r1 = sum e_t e_(t-1) / sum e_t^2 over
// consecutive rows of the same stage (not centred: a constant offset is one misfit, not noise),
// clamped to [0, 1); n_eff = n (1 - r1)/(1 + r1), floored at min(n, 5) per variable (fewer
// independent values make no criterion, and ln(n_eff) must stay a penalty). White residuals give
// n_eff = n.
struct EffectiveSize {
  std::array<std::size_t, 2> n{};  // residuals compared (0: the variable has no range)
  std::array<double, 2> rss{};     // their sum of squares
  std::array<double, 2> r1{};      // lag-1 autocorrelation
  std::array<double, 2> n_eff{};
  std::size_t total_n() const { return n[0] + n[1]; }
  double total_n_eff() const { return n_eff[0] + n_eff[1]; }
};
EffectiveSize effective_sample_size(const MeasurementFile& data, const Segmentation& seg, const Comparison& c);

}  // namespace rockdem
