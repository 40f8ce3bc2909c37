#include "framework/boundary/time_function.hpp"

#include <muParser.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <numbers>
#include <sstream>

#include "framework/core/error.hpp"

namespace rockdem {

struct TimeFunction::Expr {
  mu::Parser parser;
  double t = 0.0;
};

TimeFunction TimeFunction::constant(double v) {
  TimeFunction f;
  f.kind_ = Kind::constant;
  f.a_ = v;
  return f;
}

TimeFunction TimeFunction::table(std::vector<double> t, std::vector<double> v, double value_after,
                                 std::string origin) {
  if (t.size() != v.size() || t.empty()) throw InputError(origin + ": a table needs at least one row of (time, value)");
  for (std::size_t i = 1; i < t.size(); ++i)
    if (!(t[i] >= t[i - 1]))
      throw InputError(origin + ": time goes backwards at row " + std::to_string(i + 1) + " (" +
                       std::to_string(t[i - 1]) + " then " + std::to_string(t[i]) + ")");
  TimeFunction f;
  f.kind_ = Kind::table;
  f.t_ = std::move(t);
  f.v_ = std::move(v);
  f.b_ = value_after;
  f.text_ = origin;
  return f;
}

TimeFunction TimeFunction::from_file(const std::string& path, double time_scale, double value_scale,
                                     bool derivative) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot open the time-history file (does it exist?)");
  std::vector<double> t, v;
  std::string line;
  int ln = 0;
  while (std::getline(in, line)) {
    ++ln;
    const auto hash = line.find('#');
    if (hash != std::string::npos) line.resize(hash);
    std::replace(line.begin(), line.end(), ',', ' ');
    std::istringstream ls(line);
    double a, b;
    if (!(ls >> a)) continue;  // blank or comment line
    if (!(ls >> b) || !std::isfinite(a) || !std::isfinite(b))
      throw InputError(path + ":" + std::to_string(ln) + ": expected two numbers (time, value)");
    t.push_back(a * time_scale);
    v.push_back(b * value_scale);
  }
  return from_samples(std::move(t), std::move(v), derivative, path);
}

TimeFunction TimeFunction::from_samples(std::vector<double> t, std::vector<double> v, bool derivative,
                                        const std::string& path) {
  if (t.size() < 2) throw InputError(path + ": a time history needs at least two rows");
  if (!derivative) {
    const double last = v.back();
    return table(std::move(t), std::move(v), last, path);
  }
  // Displacement history -> velocity: the piecewise constant slope of each segment, so that the
  // driven displacement passes through the table's points.
  std::vector<double> tv, vv;
  for (std::size_t i = 1; i < t.size(); ++i) {
    const double dt = t[i] - t[i - 1];
    if (!(dt > 0.0)) throw InputError(path + ": time must increase strictly for a displacement history (row " + std::to_string(i + 1) + ")");
    const double vel = (v[i] - v[i - 1]) / dt;
    tv.push_back(t[i - 1]);
    vv.push_back(vel);
    tv.push_back(t[i]);
    vv.push_back(vel);
  }
  return table(std::move(tv), std::move(vv), 0.0, path);
}

TimeFunction TimeFunction::expression(const std::string& expr) {
  TimeFunction f;
  f.kind_ = Kind::expression;
  f.text_ = expr;
  f.expr_ = std::make_shared<Expr>();
  try {
    f.expr_->parser.DefineVar("t", &f.expr_->t);
    f.expr_->parser.DefineConst("pi", std::numbers::pi);
    f.expr_->parser.DefineConst("g", 9.80665);
    f.expr_->parser.SetExpr(expr);
    // A value that is NaN or inf at the start (sqrt(-1), 1/0) is refused here; one that becomes
    // non-finite later is stopped by the engine's per-step check (exit 3).
    const double v0 = f.expr_->parser.Eval();
    if (!std::isfinite(v0))
      throw InputError("expression '" + expr + "' is " + (std::isnan(v0) ? "not a number" : "infinite") +
                       " at t = 0 s; valid: an expression finite over the stage");
  } catch (const mu::Parser::exception_type& e) {
    throw InputError("expression '" + expr + "': " + e.GetMsg() +
                     " (variables: t [s]; constants: pi, g; functions: sin, cos, exp, abs, ...)");
  }
  return f;
}

TimeFunction TimeFunction::cycles(double amplitude, double speed, int number, bool one_sided) {
  TimeFunction f;
  f.kind_ = Kind::cycles;
  f.a_ = amplitude;
  f.b_ = speed;
  f.n_ = number;
  f.one_sided_ = one_sided;
  return f;
}

TimeFunction TimeFunction::sine(double amplitude, double frequency, double number) {
  TimeFunction f;
  f.kind_ = Kind::sine;
  f.a_ = amplitude;
  f.b_ = frequency;
  f.c_ = number;
  return f;
}

double TimeFunction::duration() const {
  switch (kind_) {
    case Kind::cycles: return (one_sided_ ? 2.0 : 4.0) * a_ / b_ * n_;
    case Kind::sine: return c_ / b_;
    case Kind::table: return t_.back();
    default: return std::numeric_limits<double>::infinity();
  }
}

namespace {
// Velocity of a triangular cycle of amplitude a at speed v (legs of duration a/v).
double cycle_vel(double t, double a, double v, bool one_sided) {
  const double leg = a / v;
  const double period = (one_sided ? 2.0 : 4.0) * leg;
  const double x = std::fmod(t, period) / leg;
  if (x < 1.0) return v;
  if (x < 3.0) return -v;
  return v;
}
}  // namespace

double TimeFunction::operator()(double t) const {
  switch (kind_) {
    case Kind::constant: return a_;
    case Kind::table: {
      if (t <= t_.front()) return v_.front();
      if (t >= t_.back()) return b_;
      const auto it = std::upper_bound(t_.begin(), t_.end(), t);
      const std::size_t i = static_cast<std::size_t>(it - t_.begin());
      const double w = (t - t_[i - 1]) / (t_[i] - t_[i - 1]);
      return v_[i - 1] + w * (v_[i] - v_[i - 1]);
    }
    case Kind::expression:
      expr_->t = t;
      return expr_->parser.Eval();
    case Kind::cycles:
      if (t < 0.0 || t >= duration()) return 0.0;
      return cycle_vel(t, a_, b_, one_sided_);
    case Kind::sine:
      if (t < 0.0 || t >= duration()) return 0.0;
      return a_ * 2.0 * std::numbers::pi * b_ * std::cos(2.0 * std::numbers::pi * b_ * t);
  }
  return 0.0;
}

std::string TimeFunction::describe() const {
  std::ostringstream os;
  switch (kind_) {
    case Kind::constant: os << "constant " << a_; break;
    case Kind::table: os << "table from " << text_ << " (" << t_.size() << " rows)"; break;
    case Kind::expression: os << "expression '" << text_ << "'"; break;
    case Kind::cycles: os << n_ << (one_sided_ ? " one-sided" : "") << " cycles of amplitude " << a_ << " m at " << b_ << " m/s"; break;
    case Kind::sine: os << "sine of amplitude " << a_ << " m, " << b_ << " Hz, " << c_ << " cycles"; break;
  }
  return os.str();
}

}  // namespace rockdem
