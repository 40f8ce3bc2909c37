#pragma once
// The velocity a rigid block's point is given over a step: its chord, (x(n+1) - x(n)) / dt, as a
// deformable block's gridpoint has, so that the contacts' increments (v dt) move it exactly where
// the block put it. The tangent at the new position, vc + omega perp(r), leaves out the chord's
// part along the arm, (omega dt)^2 r / 2 per step and always outward (docs/engine.md, time
// integration). With r the new arm and turn = omega dt, r(n) = R(-turn) r, so
// r - r(n) = sin(turn) perp(r) + (1 - cos(turn)) r.
#include <cmath>

#include "framework/core/types.hpp"

namespace rockdem {

struct RigidChord {
  double across = 0.0;   // along perp(r), 1/s: sin(turn) / dt (omega as dt -> 0)
  double outward = 0.0;  // along r, 1/s: (1 - cos(turn)) / dt, written 2 sin^2(turn/2) / dt for round-off

  // A block turning at omega over a step dt (> 0; dt = 0, before any step: the tangent).
  RigidChord(double omega, double dt) {
    if (!(dt > 0.0)) {
      across = omega;
      return;
    }
    const double turn = omega * dt, half = std::sin(0.5 * turn);
    across = std::sin(turn) / dt;
    outward = 2.0 * half * half / dt;
  }
  // The velocity of the point at arm r (from the centre, at the step's end) of a block whose
  // centre moves at vc.
  Vec2 velocity(const Vec2& vc, const Vec2& r) const { return vc + across * perp(r) + outward * r; }
};

}  // namespace rockdem
