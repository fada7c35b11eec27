// The paper's narrow phase: both objects move on straight lines from their start-of-step states, and
// the closest approach of the two lines inside the step is taken, clamped to [0, dt].
#pragma once

#include "core/conjunctions/object_step.hpp"

namespace kessler {

// The paper's formula for start positions x1, x2 [m] and velocities v1, v2 [m/s] over a step of dt_s:
// tau = -(x1 - x2).(v1 - v2) / |v1 - v2|^2, clamped to [0, dt], and the distance of the lines there.
// (The paper prints the numerator without the minus sign; the minimum of the distance of
// x1 + tau v1 and x2 + tau v2 is at the value above, which is what the paper's tool computes.)
PairMinimum linear_closest_approach(const double x1[3], const double v1[3], const double x2[3],
                                    const double v2[3], double dt_s);

// The minimum the linear narrow phase reports for objects a (lower id) and b in one step, or 0 when
// none: the step must own the approach by the boundary rule (slope negative at the start, non-negative
// at the end, both from the true end states) and the paper's distance must be <= threshold_m.
int linear_minimum(const ObjectStep& a, const ObjectStep& b, double dt_s, double threshold_m,
                   PairMinimum* out);

}  // namespace kessler
