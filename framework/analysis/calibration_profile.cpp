// Profile-likelihood intervals of fitted parameters (calibration_fit.hpp, profile_interval).
//
// The standard errors of calibrate come from the Jacobian at the optimum: a straight-line view of
// the objective that says little where a parameter sits on a bound, where the record hardly
// constrains it (an infinite or huge standard error), or where the objective is far from a
// parabola over the range that matters (rate_and_state's a, b and critical slip on a velocity-step
// record came back 2-5 times off with standard errors that did not say so). The profile walks the
// parameter itself: held at each value, the others refitted, the objective C rises from its
// optimum C0, and the value is kept while the likelihood-ratio statistic stays below the 95 %
// quantile of chi-square with one degree of freedom (Venzon & Moolgavkar 1988; Bates & Watts 1988,
// ch. 6):
//   LR = n_eff ln(C / C0) <= 3.841,
// the Gaussian likelihood ratio n ln(RSS/RSS0) with the residuals counted as the n_eff
// independent values they are worth (effective_size.hpp), and the fit's soft-L1 objective for the
// RSS (quadratic for residuals below its scale, a tenth of the variable's range).
#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "framework/analysis/calibration_fit.hpp"

namespace rockdem::calibration_detail {

namespace {
constexpr double kChi2OneDof95 = 3.841458820694124;
constexpr int kProfileIterations = 20;  // per refit of the others (warm starts need few)
constexpr int kMaxSteps = 8;            // doubling steps of at least 0.005 reach either bound
}  // namespace

ProfileInterval profile_interval(const Evaluator& ev, const std::vector<double>& x, const Eigen::MatrixXd& J, std::size_t j,
                                 double step, double n_eff, double se_unit, double loss_scale) {
  ProfileInterval out;
  std::vector<double> r;
  if (!ev.residuals(x.data(), step, r)) {
    out.ran = false;
    out.why = "the model does not run at the fitted values at the fitting step";
    return out;
  }
  const double c0 = robust_cost(r, loss_scale);
  if (!(c0 > 0.0)) {  // LR would be infinite everywhere: no interval can be read
    out.ran = false;
    out.why = "the model fits the record exactly";
    return out;
  }
  // Where the others' optimum moves as parameter j does, to first order (the profile trace of the
  // linearised problem: J_o^T J_o ds = -J_o^T J_j): each refit starts on that line, not where
  // the others stood, so that strongly coupled parameters (rate_and_state's a and b) need not
  // crawl along their narrow valley within the refit's 20 iterations. (On the coverage test's
  // velocity-step records the intervals came out the same with and without it: there the refits
  // converged either way.)
  const std::size_t kk = ev.k();
  Eigen::VectorXd trace = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(kk));
  if (kk > 1 && J.cols() == static_cast<Eigen::Index>(kk)) {
    Eigen::MatrixXd jo(J.rows(), static_cast<Eigen::Index>(kk - 1));
    for (std::size_t i = 0, c = 0; i < kk; ++i)
      if (i != j) jo.col(static_cast<Eigen::Index>(c++)) = J.col(static_cast<Eigen::Index>(i));
    const Eigen::VectorXd ds = (jo.transpose() * jo).completeOrthogonalDecomposition().solve(-(jo.transpose() * J.col(static_cast<Eigen::Index>(j))));
    for (std::size_t i = 0, c = 0; i < kk; ++i)
      if (i != j) trace(static_cast<Eigen::Index>(i)) = ds(static_cast<Eigen::Index>(c++));
  }
  // The start of a refit at u from the inside point (u_in, x_in): along the trace.
  auto start_from = [&](const std::vector<double>& x_in, double u_in, double u) {
    std::vector<double> xs = x_in;
    for (std::size_t i = 0; i < kk; ++i)
      if (i != j) xs[i] = std::clamp(x_in[i] + trace(static_cast<Eigen::Index>(i)) * (u - u_in), 0.0, 1.0);
    return xs;
  };
  // The objective with parameter j held at u, the others refitted from xw (their optimum left in it).
  auto refit_at = [&](double u, std::vector<double>& xw) {
    xw[j] = u;
    if (ev.k() > 1) {
      std::atomic<int> iterations{0};
      solve(ev, xw, step, kProfileIterations, loss_scale, iterations, 0.0, true, static_cast<int>(j));
    }
    ++out.fits;
    std::vector<double> rw;
    const double c = ev.residuals(xw.data(), step, rw) ? robust_cost(rw, loss_scale) : std::numeric_limits<double>::infinity();
    if (c < out.lowest * c0) {  // the profile found a lower objective than the fit's optimum
      out.lowest = c / c0;
      out.lowest_at = u;
      out.lowest_x = xw;
    }
    return c;
  };
  // LR statistic; a model that cannot run there (inf, NaN) is outside.
  auto statistic = [&](double c) {
    const double lr = n_eff * std::log(c / c0);
    return std::isnan(lr) ? std::numeric_limits<double>::infinity() : lr;
  };
  for (const int side : {-1, 1}) {
    const double edge = side < 0 ? 0.0 : 1.0;
    ProfileEnd& end = side < 0 ? out.lower : out.upper;
    end = {edge, true};
    double u_in = x[j], lr_in = 0.0;
    std::vector<double> x_in = x;
    // Refits at u; an inside point becomes the next start. Returns LR.
    auto try_at = [&](double u) {
      std::vector<double> xw = start_from(x_in, u_in, u);
      double lr = statistic(refit_at(u, xw));
      if (!std::isfinite(lr)) {  // perhaps the start on the trace cannot run: from the inside point
        xw = x_in;
        lr = statistic(refit_at(u, xw));
      }
      if (lr <= kChi2OneDof95) {
        u_in = u;
        lr_in = lr;
        x_in = std::move(xw);
      }
      return lr;
    };
    double h = std::isfinite(se_unit) ? std::clamp(2.0 * se_unit, 0.005, 0.25) : 0.05;
    for (int n = 0; n < kMaxSteps && u_in != edge; ++n, h *= 2.0) {
      const double u = side < 0 ? std::max(0.0, u_in - h) : std::min(1.0, u_in + h);
      const double lr = try_at(u);
      if (lr <= kChi2OneDof95) continue;
      // Crossed between u_in and u: two bisections, then the crossing interpolated.
      double u_out = u, lr_out = lr;
      for (int m = 0; m < 2; ++m) {
        const double um = 0.5 * (u_in + u_out);
        const double lrm = try_at(um);
        if (lrm > kChi2OneDof95) {
          u_out = um;
          lr_out = lrm;
        }
      }
      // On the signed root of LR, which is linear in the parameter where the objective is a
      // parabola (LR itself is not: interpolated linearly, the ends of rate_and_state's a on a
      // velocity-step record with every increment kept came in at 0.59 of the linearised
      // interval's half-width, and at 1.03 on the root).
      const double root_in = std::sqrt(std::max(lr_in, 0.0)), root_out = std::sqrt(lr_out);
      const double t = std::isfinite(root_out) && root_out > root_in ? (std::sqrt(kChi2OneDof95) - root_in) / (root_out - root_in) : 0.5;
      end = {u_in + std::clamp(t, 0.0, 1.0) * (u_out - u_in), false};
      break;
    }
  }
  return out;
}

}  // namespace rockdem::calibration_detail
