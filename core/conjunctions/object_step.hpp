// One object's motion over one step as the narrow phases see it: its states at both ends, and the
// motion models between them (the paper's straight line, and the cubic Hermite curve).
#pragma once

#include <cstddef>

#include "core/population/population.hpp"

namespace kessler {

// Start and end states of one object over one step: TEME of epoch, m and m/s.
struct ObjectStep {
  double p0[3], v0[3];  // at the start of the step
  double p1[3], v1[3];  // at the end of the step
};

inline ObjectStep gather_object_step(const StateArrays& start, const StateArrays& end, std::size_t i) {
  return ObjectStep{{start.x[i], start.y[i], start.z[i]},
                    {start.vx[i], start.vy[i], start.vz[i]},
                    {end.x[i], end.y[i], end.z[i]},
                    {end.vx[i], end.vy[i], end.vz[i]}};
}

// A local minimum of a pair's distance inside one step.
struct PairMinimum {
  double tau_s = 0.0;  // time since the start of the step, in (0, dt]
  double distance_m = 0.0;
};

// At most this many minima of one pair in one step are reported (the Hermite distance has at most
// three local minima on a step: its derivative is a degree-5 polynomial).
inline constexpr int kMaxMinimaPerStep = 3;

// Position and velocity on the cubic Hermite curve through both end states at tau_s in [0, dt_s].
void hermite_state(const ObjectStep& o, double dt_s, double tau_s, double r_m[3], double v_m_s[3]);

// Position and velocity on the paper's straight line from the start state at tau_s.
void linear_state(const ObjectStep& o, double tau_s, double r_m[3], double v_m_s[3]);

}  // namespace kessler
