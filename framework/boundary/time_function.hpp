#pragma once
// Scalar functions of time for boundary conditions (velocities, tractions) and for element paths:
// a constant, a table from a file, an expression (muparser, variable t), triangular displacement
// cycles at constant speed, or a sinusoidal displacement.
#include <memory>
#include <string>
#include <vector>

namespace rockdem {

class TimeFunction {
 public:
  enum class Kind { constant, table, expression, cycles, sine };

  static TimeFunction constant(double v);
  // Table of (time, value); linear between rows, `value_after` after the last row.
  static TimeFunction table(std::vector<double> t, std::vector<double> v, double value_after,
                            std::string origin);
  // Read a two-column text file (time, value; '#' comments, commas or blanks), scaled by `scale`.
  // `derivative`: the file holds a displacement history and the function is its velocity.
  static TimeFunction from_file(const std::string& path, double time_scale, double value_scale,
                                bool derivative);
  // The same from samples already read (e.g. named columns of a CSV table); `origin` for messages.
  static TimeFunction from_samples(std::vector<double> t, std::vector<double> v, bool derivative,
                                   const std::string& origin);
  static TimeFunction expression(const std::string& expr);  // throws InputError on a bad expression
  // Velocity of a triangular displacement history: 0 -> +A -> 0 (one_sided) or
  // 0 -> +A -> 0 -> -A -> 0, `number` times, at speed `speed`; zero afterwards.
  static TimeFunction cycles(double amplitude, double speed, int number, bool one_sided);
  // Velocity of the displacement A sin(2 pi f t) for `number` cycles; zero afterwards.
  static TimeFunction sine(double amplitude, double frequency, double number);

  double operator()(double t) const;  // value (velocity for motion histories)
  double duration() const;            // time after which the history is finished (inf if none)
  Kind kind() const { return kind_; }
  std::string describe() const;

 private:
  Kind kind_ = Kind::constant;
  double a_ = 0.0, b_ = 0.0, c_ = 0.0;
  int n_ = 0;
  bool one_sided_ = false;
  std::vector<double> t_, v_;
  std::string text_;
  struct Expr;
  std::shared_ptr<Expr> expr_;
};

}  // namespace rockdem
