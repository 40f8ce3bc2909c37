#pragma once
// One-dimensional root refinement shared by the solvers that bracket a sign change of a scalar
// function: the element driver's scan for a continuous sign change of its normal residual and the
// virtual shear box's search for the slip that balances its loading chain. Both stop on a test of
// the residual of their own (|g| within a tolerance; a point on one side of the root), which the
// bracketing solvers of Boost.Math, whose stop test sees only the bracket, do not take.
#include <algorithm>
#include <cmath>

namespace rockdem::root_finding {

// A bracket [a, b] (in either order) with f(a) and f(b) of opposite signs.
struct Bracket {
  double a, fa, b, fb;
};

// The Illinois method (Dowell & Jarratt 1971): regula falsi that halves the stored value of an
// end that keeps its place twice in a row, so that a convex f does not leave one end fixed and
// the convergence stays superlinear. Each new point c is evaluated once (fc = f(c)) and replaces
// the end whose value has the sign of fc; then `stop(c, fc)` ends the refinement (returns true).
// It also ends, returning false, after `max_iter` evaluations or when the bracket is no wider
// than abs_width + rel_width |c|: for a continuous f that is the root to rounding, for a jump it
// is the jump. A point the secant puts outside the bracket (rounding) is replaced by the midpoint.
// `br` holds the final bracket.
template <class F, class Stop>
bool illinois(F&& f, Bracket& br, int max_iter, double abs_width, double rel_width, Stop&& stop) {
  int kept = 0;  // +1: a kept its place last time, -1: b did
  for (int it = 0; it < max_iter; ++it) {
    double c = (br.a * br.fb - br.b * br.fa) / (br.fb - br.fa);
    if (!(c > std::min(br.a, br.b) && c < std::max(br.a, br.b))) c = 0.5 * (br.a + br.b);
    const double fc = f(c);
    if ((fc > 0.0) == (br.fb > 0.0)) {
      br.b = c;
      br.fb = fc;
      if (kept == 1) br.fa *= 0.5;
      kept = 1;
    } else {
      br.a = c;
      br.fa = fc;
      if (kept == -1) br.fb *= 0.5;
      kept = -1;
    }
    if (stop(c, fc)) return true;
    if (std::abs(br.b - br.a) <= abs_width + rel_width * std::abs(c)) return false;
  }
  return false;
}

}  // namespace rockdem::root_finding
