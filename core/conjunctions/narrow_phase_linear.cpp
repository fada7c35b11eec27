#include "core/conjunctions/narrow_phase_linear.hpp"

#include <algorithm>
#include <cmath>

#include "core/conjunctions/boundary_rule.hpp"

namespace kessler {

PairMinimum linear_closest_approach(const double x1[3], const double v1[3], const double x2[3],
                                    const double v2[3], double dt_s) {
  double dx[3], dv[3];
  for (int k = 0; k < 3; ++k) {
    dx[k] = x1[k] - x2[k];
    dv[k] = v1[k] - v2[k];
  }
  const double dx_dv = dx[0] * dv[0] + dx[1] * dv[1] + dx[2] * dv[2];
  const double dv_dv = dv[0] * dv[0] + dv[1] * dv[1] + dv[2] * dv[2];
  // Equal velocities: the distance is constant; the paper's first case (tau = 0) applies.
  const double tau = dv_dv > 0.0 ? std::clamp(-dx_dv / dv_dv, 0.0, dt_s) : 0.0;
  double d2 = 0.0;
  for (int k = 0; k < 3; ++k) {
    const double c = dx[k] + tau * dv[k];
    d2 += c * c;
  }
  return PairMinimum{tau, std::sqrt(d2)};
}

int linear_minimum(const ObjectStep& a, const ObjectStep& b, double dt_s, double threshold_m,
                   PairMinimum* out) {
  const double g_start = boundary_slope(a.p0, a.v0, b.p0, b.v0);
  if (!(g_start < 0.0)) return 0;
  const double g_end = boundary_slope(a.p1, a.v1, b.p1, b.v1);
  if (g_end < 0.0) return 0;  // still approaching at the end: the next step owns the minimum
  const PairMinimum m = linear_closest_approach(a.p0, a.v0, b.p0, b.v0, dt_s);
  if (!(m.distance_m <= threshold_m)) return 0;
  out[0] = m;
  return 1;
}

}  // namespace kessler
