// Which step reports a close approach: the rule that makes every local minimum of a pair's distance
// come out once, also when it falls exactly on a step boundary, with no state carried across steps.
//
// The pair's squared distance D(t) = |dp(t)|^2 has the slope D'(t) = 2 dp(t) . dv(t). At a step
// boundary both neighbouring steps see the very same end states, so both compute the very same number
// g = dp . dv there (same expression, same operands, lower id first: bitwise equal). A minimum is where
// the slope goes from negative to non-negative. Each step owns the half-open interval (t0, t0 + dt]:
//   - a step reports the transitions "g < 0, then >= 0" strictly after its start and up to its end;
//   - a minimum exactly on a boundary (g == 0 there, decreasing before) has g >= 0 at the end of the
//     earlier step, so the earlier step reports it at tau = dt; the later step starts with g >= 0 and
//     sees no transition at its start;
//   - a minimum just before a boundary (g > 0 at the boundary) belongs to the earlier step, one just
//     after it (g < 0 at the boundary) to the later one. Both steps agree on the sign, so a minimum is
//     never reported twice nor lost.
// A pair already receding at the first instant of a run (g >= 0 at t = 0) had its minimum before the
// run: it is not an encounter of the run.
#pragma once

namespace kessler {

// Half the slope of the squared distance at a step boundary: (p1 - p2) . (v1 - v2), object 1 being the
// lower id. Written out so that every caller computes it in the same order.
inline double boundary_slope(const double p1[3], const double v1[3], const double p2[3], const double v2[3]) {
  const double dx = p1[0] - p2[0], dy = p1[1] - p2[1], dz = p1[2] - p2[2];
  const double dvx = v1[0] - v2[0], dvy = v1[1] - v2[1], dvz = v1[2] - v2[2];
  return dx * dvx + dy * dvy + dz * dvz;
}

}  // namespace kessler
