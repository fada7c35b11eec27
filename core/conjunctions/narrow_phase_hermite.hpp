// The default narrow phase: each object follows the cubic Hermite curve through its states at both ends
// of the step, so positions and velocities are continuous across steps. The pair's squared distance is
// then a degree-6 polynomial of time; its local minima on the step are found exactly (every one, by
// Bernstein root isolation of its derivative) and refined to far below 1e-6 s.
#pragma once

#include "core/conjunctions/object_step.hpp"

namespace kessler {

// The local minima of the distance of objects a (lower id) and b in (0, dt], owned by this step under
// the boundary rule (boundary_rule.hpp), whose distance is <= threshold_m, in time order. Returns how
// many were written to out (at most kMaxMinimaPerStep).
int hermite_minima(const ObjectStep& a, const ObjectStep& b, double dt_s, double threshold_m,
                   PairMinimum* out);

}  // namespace kessler
