#include "framework/analysis/calibration_fit.hpp"

#include "framework/core/error.hpp"
#include "framework/core/si_raw_value.hpp"

#include <algorithm>
#include <bit>
#include <cstdint>
#include <thread>

namespace rockdem::calibration_detail {
namespace {

// The finite-difference Jacobian at x, whose residuals at `step` are r, taken at `jacobian_step`
// where that is another positive step and the model runs there (from its own residuals at x, one
// run more), else at `step`. Why: at the fine step a run costs as many as ten at the fitting
// step, while the two steps' sensitivities differ far less than their residuals (their NRMSEs
// differ by a few per cent where the polish runs).
bool jacobian_at(const Evaluator& ev, const double* x, const std::vector<double>& r, double step, double jacobian_step,
                 Eigen::MatrixXd& J) {
  if (jacobian_step > 0.0 && jacobian_step != step) {
    std::vector<double> rj;
    if (ev.residuals(x, jacobian_step, rj) && rj.size() == r.size()) return ev.jacobian(x, rj, jacobian_step, J);
  }
  return ev.jacobian(x, r, step, J);
}

// Residuals and Jacobian at the last point Ceres asked for, shared by the one-residual blocks
// (one block per residual, so that the robust loss acts on each residual, not on their sum).
class SharedResiduals {
 public:
  SharedResiduals(const Evaluator& ev, double step, double jacobian_step)
      : ev_(ev), step_(step), jacobian_step_(jacobian_step) {}
  bool at(const double* x, bool need_jacobian) {
    const std::size_t kk = ev_.k();
    if (!(have_ && std::equal(x, x + kk, x_.begin()))) {
      x_.assign(x, x + kk);
      have_ = true;
      have_j_ = false;
      ok_ = ev_.residuals(x, step_, r_);
    }
    if (ok_ && need_jacobian && !have_j_) {
      ok_j_ = jacobian_at(ev_, x, r_, step_, jacobian_step_, J_);
      have_j_ = true;
    }
    return ok_ && (!need_jacobian || ok_j_);
  }
  double r(std::size_t i) const { return r_[i]; }
  double j(std::size_t i, std::size_t c) const {
    return J_(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(c));
  }

 private:
  const Evaluator& ev_;
  double step_, jacobian_step_;
  std::vector<double> x_, r_;
  Eigen::MatrixXd J_;
  bool have_ = false, have_j_ = false, ok_ = false, ok_j_ = false;
};

class RowCost final : public ceres::CostFunction {
 public:
  RowCost(SharedResiduals& s, std::size_t row, int k) : s_(s), row_(row) {
    set_num_residuals(1);
    mutable_parameter_block_sizes()->push_back(k);
  }
  bool Evaluate(double const* const* p, double* residuals, double** jacobians) const override {
    const bool need_j = jacobians != nullptr && jacobians[0] != nullptr;
    if (!s_.at(p[0], need_j)) return false;
    residuals[0] = s_.r(row_);
    if (need_j) {
      const auto kk = static_cast<std::size_t>(parameter_block_sizes()[0]);
      for (std::size_t c = 0; c < kk; ++c) jacobians[0][c] = s_.j(row_, c);
    }
    return true;
  }

 private:
  SharedResiduals& s_;
  std::size_t row_;
};

}  // namespace

bool log_dimension(Dimension d) {
  return d == Dimension::stiffness || d == Dimension::length || d == Dimension::stress ||
         d == Dimension::energy_per_area || d == Dimension::velocity;
}

std::pair<double, double> physical_range(Dimension d) {
  switch (d) {
    case Dimension::stiffness: return {1e8, 1e13};        // 0.1 GPa/m .. 10 000 GPa/m
    case Dimension::angle: return {0.0, 80.0 * kDeg};
    case Dimension::length: return {1e-6, 1.0};
    case Dimension::stress: return {1e4, 1e10};
    case Dimension::energy_per_area: return {1.0, 1e9};
    case Dimension::velocity: return {1e-9, 10.0};
    default: return {-100.0, 100.0};
  }
}

Evaluator::Evaluator(const MeasurementFile& data, const Segmentation& seg, const CalibrationOptions& opt,
                     std::vector<Slot> slots, std::vector<std::size_t> free, std::vector<ElementStage> stages)
    : data_(data), seg_(seg), opt_(opt), slots_(std::move(slots)), free_(std::move(free)), stages_(std::move(stages)) {
  for (std::size_t v = 0; v < 2; ++v) {
    double lo = kInf, hi = -kInf;
    for (const auto& r : data_.rows) {
      lo = std::min(lo, compared_value(r, v));
      hi = std::max(hi, compared_value(r, v));
    }
    range_[v] = data_.rows.empty() ? 0.0 : hi - lo;
  }
}

std::unique_ptr<JointModel> Evaluator::build(const std::vector<double>& v) const {
  RawValues law = opt_.law_values;
  std::vector<EffectSpec> effects(opt_.effects.size());
  for (std::size_t e = 0; e < effects.size(); ++e) {
    effects[e].name = opt_.effects[e];
    effects[e].where = "calibration";
    if (auto it = opt_.effect_values.find(opt_.effects[e]); it != opt_.effect_values.end()) effects[e].params = it->second;
  }
  for (std::size_t i = 0; i < slots_.size(); ++i) {
    const Slot& s = slots_[i];
    if (std::isinf(v[i])) continue;  // only defaults are infinite: leave them out
    RawValues& target = s.effect < 0 ? law : effects[static_cast<std::size_t>(s.effect)].params;
    target[s.info.name] = si_raw_value(v[i], s.info.dim, "calibration");
  }
  return make_joint_model(opt_.law, law, effects, "calibration");
}

MeasurementFile Evaluator::run(const JointModel& model, double step, Misses* misses, bool extra) const {
  ElementOptions eo = opt_.element;
  eo.max_step = step;
  eo.output_every = 1;
  eo.extra_columns = extra;
  ElementDriver driver(model, eo);
  ++evaluations_;
  MeasurementFile rec = driver.run(stages_);
  if (misses) *misses = {driver.unconverged_steps(), driver.steps()};
  return rec;
}

std::string Evaluator::describe(const double* x) const {
  std::string out;
  for (std::size_t j = 0; j < free_.size(); ++j) {
    const Slot& s = slots_[free_[j]];
    out += (out.empty() ? "" : ", ") + s.name + " = " + format_quantity(to_si(j, x[j]), s.info.dim);
  }
  return out.empty() ? "no free parameters" : out;
}

bool Evaluator::residuals(const double* x, double step, std::vector<double>& r, Comparison* out,
                          MeasurementFile* record, std::string* why, Misses* misses) const {
  try {
    const auto model = build(values(x));
    MeasurementFile rec = run(*model, step, misses, record != nullptr);
    const bool placing = !out && placing_pays();
    std::shared_ptr<const Placement> known = placing ? placement(step, rec) : nullptr;
    if (placing) ++(known ? placement_hits_ : placement_misses_);
    Comparison c;
    if (known) {
      if (std::string differs = normal_stress_mismatch(seg_, rec, known->stages, opt_.compare); !differs.empty())
        throw InputError(differs);
    } else {
      c = out ? compare(data_, seg_, rec, opt_.compare) : align_records(data_, seg_, rec, opt_.compare);
      if (placing_pays()) remember(step, rec, c);
    }
    const std::vector<AlignedRow>& placed = known ? known->rows : c.alignment.rows;
    r.clear();
    r.reserve(n());
    for (std::size_t v = 0; v < 2; ++v) {
      if (!(range_[v] > 0.0)) continue;
      for (std::size_t i = 0; i < data_.rows.size(); ++i) {
        const double d = (aligned_value(placed[i], rec, v) - compared_value(data_.rows[i], v)) / range_[v];
        r.push_back(std::isfinite(d) ? d : 10.0);
      }
    }
    if (out) *out = std::move(c);
    if (record) *record = std::move(rec);
    return true;
  } catch (const std::exception& e) {
    if (why) *why = e.what();
    return false;
  }
}

namespace {
bool same_bits(double a, double b) { return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b); }
}  // namespace

std::shared_ptr<const Evaluator::Placement> Evaluator::placement(double step, const MeasurementFile& rec) const {
  std::shared_ptr<const Placement> p;
  {
    const std::lock_guard<std::mutex> lock(placements_mutex_);
    for (const auto& q : placements_)
      if (q->step == step) p = q;
  }
  if (!p || p->stage.size() != rec.rows.size()) return nullptr;
  // Bitwise: a placement is reused only where align() would read the very same numbers.
  for (std::size_t i = 0; i < rec.rows.size(); ++i) {
    const MeasurementRow& q = rec.rows[i];
    if (p->stage[i] != q.stage || !same_bits(p->shear[i], q.shear_disp_mm) || !same_bits(p->time[i], q.time_s))
      return nullptr;
  }
  return p;
}

void Evaluator::remember(double step, const MeasurementFile& rec, const Comparison& c) const {
  auto p = std::make_shared<Placement>();
  p->step = step;
  for (const MeasurementRow& q : rec.rows) {
    p->stage.push_back(q.stage);
    p->time.push_back(q.time_s);
    p->shear.push_back(q.shear_disp_mm);
  }
  p->stages = c.model_segments.stages;
  p->rows = c.alignment.rows;
  const std::lock_guard<std::mutex> lock(placements_mutex_);
  std::erase_if(placements_, [&](const auto& q) { return q->step == step; });
  placements_.insert(placements_.begin(), std::move(p));
  if (placements_.size() > 2) placements_.pop_back();  // the fitting step and the fine one
}

bool Evaluator::jacobian(const double* x, const std::vector<double>& r0, double step, Eigen::MatrixXd& J) const {
  const std::size_t kk = k(), nn = r0.size();
  J.setZero(static_cast<Eigen::Index>(nn), static_cast<Eigen::Index>(kk));
  std::atomic<std::size_t> next{0};
  auto work = [&] {
    std::vector<double> xp(x, x + kk), r;
    for (std::size_t j = next++; j < kk; j = next++) {
      // Forward step (backward at the upper bound); where the model cannot run there, the
      // other side; where neither runs, the column stays zero (no usable sensitivity) rather
      // than failing the whole step.
      double h = xp[j] + opt_.fd_step <= 1.0 ? opt_.fd_step : -opt_.fd_step;
      xp[j] = x[j] + h;
      bool got = residuals(xp.data(), step, r) && r.size() == nn;
      if (!got && x[j] - h >= 0.0 && x[j] - h <= 1.0) {
        h = -h;
        xp[j] = x[j] + h;
        got = residuals(xp.data(), step, r) && r.size() == nn;
      }
      if (got) {
        for (std::size_t i = 0; i < nn; ++i)
          J(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = (r[i] - r0[i]) / h;
      }
      xp[j] = x[j];
    }
  };
  const std::size_t nt = std::min<std::size_t>(static_cast<std::size_t>(std::max(1, opt_.threads)), kk);
  std::vector<std::thread> pool;
  for (std::size_t t = 1; t < nt; ++t) pool.emplace_back(work);
  work();
  for (auto& t : pool) t.join();
  return true;
}

double robust_cost(const std::vector<double>& r, double c) {
  const ceres::SoftLOneLoss loss(c > 0.0 ? c : 1.0);
  double sum = 0.0;
  for (double v : r) {
    double rho[3];
    loss.Evaluate(v * v, rho);
    sum += c > 0.0 ? rho[0] : v * v;
  }
  return 0.5 * sum;
}

ceres::Solver::Summary solve(const Evaluator& ev, std::vector<double>& xs, double step, int max_iterations, double loss_scale,
                             std::atomic<int>& iterations, double jacobian_step, bool near_optimum, int fixed) {
  SharedResiduals shared(ev, step, jacobian_step);
  ceres::Problem::Options po;
  po.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(po);
  std::unique_ptr<ceres::LossFunction> loss;
  if (loss_scale > 0.0) loss = std::make_unique<ceres::SoftLOneLoss>(loss_scale);
  const std::size_t nn = ev.n(), kk = ev.k();
  for (std::size_t i = 0; i < nn; ++i)
    problem.AddResidualBlock(new RowCost(shared, i, static_cast<int>(kk)), loss.get(), xs.data());
  for (std::size_t j = 0; j < kk; ++j) {
    problem.SetParameterLowerBound(xs.data(), static_cast<int>(j), 0.0);
    problem.SetParameterUpperBound(xs.data(), static_cast<int>(j), 1.0);
  }
  if (fixed >= 0) problem.SetManifold(xs.data(), new ceres::SubsetManifold(static_cast<int>(kk), {fixed}));
  ceres::Solver::Options so;
  so.minimizer_type = ceres::TRUST_REGION;
  so.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
  so.linear_solver_type = ceres::DENSE_QR;
  so.max_num_iterations = max_iterations;
  if (jacobian_step > step || near_optimum) {
    // The fine-step polish starts next to an optimum. From Ceres's default radius (1e4, a
    // Gauss-Newton step) its first step ran far along the record's flat directions (a stiffness at
    // its bound) and was refused again and again while the radius halved: 85 fine runs before the
    // first accepted step on test 14's twin (Mohr-Coulomb), 5.3 s of the fit's 6.2. From 1: 51
    // runs in all, 1.1-1.4 s, and a lower cost (combined NRMSE 0.2549 against 0.2557).
    so.initial_trust_region_radius = 1.0;
  }
  // With bounds, Ceres's trust region searches along each step (a projected line search). Its
  // default cubic interpolation asks for the gradient at every trial point, and a gradient here
  // is a finite-difference Jacobian, k model runs: on test 14's twin (MC + dilation_recovery,
  // k = 5) the fit made 940 runs in 18 iterations, 72 Jacobians in the fine step's 8. Quadratic
  // interpolation needs the function values only: 240 runs, the same optimum to 2e-5 in NRMSE.
  so.line_search_interpolation_type = ceres::QUADRATIC;
  so.function_tolerance = 1e-5;
  so.parameter_tolerance = 1e-4;
  so.gradient_tolerance = 1e-8;
  so.num_threads = 1;  // our Jacobian columns run in parallel instead
  so.logging_type = ceres::SILENT;
  so.minimizer_progress_to_stdout = false;
  ceres::Solver::Summary summary;
  ceres::Solve(so, &problem, &summary);
  iterations += static_cast<int>(summary.iterations.size());
  return summary;
}

Eigen::VectorXd unit_standard_errors(const Evaluator& ev, const std::vector<double>& x, const std::vector<double>& r,
                                     double step, CalibrationResult& res) {
  const std::size_t kk = x.size();
  Eigen::VectorXd se_x = Eigen::VectorXd::Constant(static_cast<Eigen::Index>(kk), kInf);
  if (kk == 0) return se_x;
  Eigen::MatrixXd J;
  if (!ev.jacobian(x.data(), r, step, J)) {
    res.warnings.push_back("the Jacobian at the optimum could not be evaluated: no standard errors");
    return se_x;
  }
  const Eigen::MatrixXd JtJ = J.transpose() * J;
  const double s2 = res.n > kk ? res.rss / static_cast<double>(res.n - kk) : 0.0;
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(JtJ);
  const double lmax = eig.eigenvalues().maxCoeff();
  // Pseudo-inverse: directions the data do not constrain (eigenvalue below 1e-10 of the
  // largest) get an infinite standard error instead of a huge finite one.
  Eigen::VectorXd var = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(kk));
  std::vector<bool> flat(kk, false);
  for (Eigen::Index a = 0; a < static_cast<Eigen::Index>(kk); ++a) {
    const double l = eig.eigenvalues()(a);
    const Eigen::VectorXd v = eig.eigenvectors().col(a);
    if (!(l > 1e-10 * lmax) || !(lmax > 0.0)) {
      for (Eigen::Index j = 0; j < static_cast<Eigen::Index>(kk); ++j)
        if (std::abs(v(j)) > 0.1) flat[static_cast<std::size_t>(j)] = true;
      continue;
    }
    var += v.cwiseProduct(v) / l;
  }
  for (std::size_t j = 0; j < kk; ++j)
    se_x(static_cast<Eigen::Index>(j)) = flat[j] ? kInf : std::sqrt(s2 * var(static_cast<Eigen::Index>(j)));
  return se_x;
}

}  // namespace rockdem::calibration_detail
