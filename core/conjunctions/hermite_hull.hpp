// The Hermite narrow phase's two cheap filters (narrow_phase_hermite.cpp), on single-precision copies of
// the objects' Bezier control points, made conservative by a bound of their rounding. The broad phase
// runs it on each pair whose boxes overlap, while the pair's data is in cache: in dense populations most
// such pairs are far apart at every instant (their boxes overlap, but not at the same time), and this
// test drops them before the narrow phase reads any state.
//
// Why it never drops a pair the narrow phase would report. Each stored coordinate is within slack_m of
// the exact control point (rounding to nearest moves a float by at most 2^-24 of its value; slack_m is
// 2^-23 of the object's largest coordinate), so each coordinate of the pair's relative control points
// is within sigma = slack_a + slack_b of the exact ones, and every point of the relative curve within
// sqrt(3) sigma (the Bernstein weights sum to 1). The filters are the narrow phase's own, widened by
// that much plus 1 mm against rounding in double:
//   1. the hull's box must reach the threshold cube around the origin;
//   2. the curve stays within 3/4 max|e_i| of its chord (e_i: the inner control points' offsets from
//      the chord's own), so the chord must come within threshold + that bound.
#pragma once

#include <algorithm>
#include <cmath>

#include "core/conjunctions/object_step.hpp"

namespace kessler {

struct alignas(64) HermiteHull {
  float point[4][3];  // Bezier control points of the step: p0, p0 + dt v0 / 3, p1 - dt v1 / 3, p1 [m]
  float share_m;      // the object's share of the threshold [m], rounded up
  float slack_m;      // bound of the rounding of any coordinate above [m]
};

// The bound of the rounding of a hull whose largest coordinate magnitude is max_abs_m.
inline float hull_slack_m(double max_abs_m) {
  return static_cast<float>(max_abs_m * 0x1p-23 * 1.0001);
}

// The hull of one object's step of dt_s with threshold share share_m.
inline HermiteHull hermite_hull(const ObjectStep& o, double dt_s, double share_m) {
  const double reach = dt_s / 3.0;
  HermiteHull hull;
  double largest = 0.0;
  for (int k = 0; k < 3; ++k) {
    const double c[4] = {o.p0[k], o.p0[k] + reach * o.v0[k], o.p1[k] - reach * o.v1[k], o.p1[k]};
    for (int p = 0; p < 4; ++p) {
      hull.point[p][k] = static_cast<float>(c[p]);
      largest = std::max(largest, std::fabs(c[p]));
    }
  }
  // Rounded up: moved out by 2^-22 before rounding to nearest (as the grid's float boxes).
  hull.share_m = static_cast<float>(share_m + share_m * 0x1p-22);
  hull.slack_m = hull_slack_m(largest);
  return hull;
}

// False only when objects a and b cannot come within share_a + share_b of each other during the step.
inline bool hulls_may_come_within(const HermiteHull& a, const HermiteHull& b) {
  constexpr double kMargin_m = 1e-3;
  const double sigma = double{a.slack_m} + double{b.slack_m};
  const double threshold = double{a.share_m} + double{b.share_m};
  double c[4][3];
  for (int p = 0; p < 4; ++p)
    for (int k = 0; k < 3; ++k) c[p][k] = double{a.point[p][k]} - double{b.point[p][k]};  // exact
  const double reach1 = threshold + sigma + kMargin_m;
  for (int k = 0; k < 3; ++k) {
    const double lo = std::min(std::min(c[0][k], c[1][k]), std::min(c[2][k], c[3][k]));
    const double hi = std::max(std::max(c[0][k], c[1][k]), std::max(c[2][k], c[3][k]));
    if (lo > reach1 || hi < -reach1) return false;
  }
  double u[3], e1 = 0.0, e2 = 0.0, uu = 0.0, c0u = 0.0;
  for (int k = 0; k < 3; ++k) {
    u[k] = c[3][k] - c[0][k];
    const double o1 = c[1][k] - (c[0][k] + u[k] / 3.0), o2 = c[2][k] - (c[0][k] + 2.0 * u[k] / 3.0);
    e1 += o1 * o1;
    e2 += o2 * o2;
    uu += u[k] * u[k];
    c0u += c[0][k] * u[k];
  }
  const double s = uu > 0.0 ? std::clamp(-c0u / uu, 0.0, 1.0) : 0.0;
  double chord2 = 0.0;
  for (int k = 0; k < 3; ++k) {
    const double w = c[0][k] + s * u[k];
    chord2 += w * w;
  }
  const double reach2 =
      threshold + 0.75 * std::sqrt(std::max(e1, e2)) + 1.7320508075688772 * sigma + kMargin_m;
  return chord2 <= reach2 * reach2 * (1.0 + 1e-9);
}

}  // namespace kessler
