#include "core/conjunctions/narrow_phase_hermite.hpp"

#include <algorithm>
#include <cmath>

#include "core/conjunctions/boundary_rule.hpp"

namespace kessler {
namespace {

// The relative curve dp(s) = a0 + a1 s + a2 s^2 + a3 s^3 with s = tau / dt in [0, 1] (object a minus
// object b), in power form for accurate evaluation near the minimum.
struct RelativeCubic {
  double a0[3], a1[3], a2[3], a3[3];

  // f(s) = dp(s) . dp'(s): half the slope of the squared distance (per unit s), and its derivative.
  void slope(double s, double& f, double& df) const {
    f = 0.0;
    df = 0.0;
    for (int k = 0; k < 3; ++k) {
      const double r = ((a3[k] * s + a2[k]) * s + a1[k]) * s + a0[k];
      const double r1 = (3.0 * a3[k] * s + 2.0 * a2[k]) * s + a1[k];
      const double r2 = 6.0 * a3[k] * s + 2.0 * a2[k];
      f += r * r1;
      df += r1 * r1 + r * r2;
    }
  }
  double distance2(double s) const {
    double d2 = 0.0;
    for (int k = 0; k < 3; ++k) {
      const double r = ((a3[k] * s + a2[k]) * s + a1[k]) * s + a0[k];
      d2 += r * r;
    }
    return d2;
  }
};

inline double dot3(const double a[3], const double b[3]) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

// Degree-5 Bernstein coefficients of f on an interval.
struct Bernstein5 {
  double c[6];
  bool negative(int k) const { return c[k] < 0.0; }
  // Class changes (negative / non-negative) along the coefficients.
  int variations() const {
    int v = 0;
    for (int k = 1; k < 6; ++k) v += negative(k) != negative(k - 1);
    return v;
  }
  // de Casteljau split at the midpoint.
  void split(Bernstein5& left, Bernstein5& right) const {
    double w[6];
    for (int k = 0; k < 6; ++k) w[k] = c[k];
    left.c[0] = w[0];
    right.c[5] = w[5];
    for (int level = 1; level < 6; ++level) {
      for (int k = 0; k < 6 - level; ++k) w[k] = 0.5 * (w[k] + w[k + 1]);
      left.c[level] = w[0];
      right.c[5 - level] = w[5 - level];
    }
  }
};

// Refines the root of f in [lo, hi] where f(lo) < 0 <= f(hi): Newton steps kept inside a bisection
// bracket, to 1e-9 of the step (1e-8 s at dt = 10 s).
double refine_root(const RelativeCubic& rel, double lo, double hi) {
  constexpr double kTolerance = 1e-9;
  double x = 0.5 * (lo + hi);
  for (int iteration = 0; iteration < 100; ++iteration) {
    double f, df;
    rel.slope(x, f, df);
    if (f == 0.0) return x;
    if (f < 0.0)
      lo = x;
    else
      hi = x;
    if (hi - lo <= kTolerance) break;
    const double newton = df > 0.0 ? x - f / df : lo - 1.0;
    if (newton > lo && newton < hi) {
      const bool converged = std::fabs(newton - x) <= 0.25 * kTolerance;
      x = newton;
      if (converged) break;
    } else {
      x = 0.5 * (lo + hi);
    }
  }
  // The closest of the last iterate and the bracket's ends (a minimum exactly at the end of the step,
  // slope exactly zero there, stays exactly there).
  double best = std::clamp(x, lo, hi), best_d2 = rel.distance2(best);
  for (double candidate : {hi, lo}) {
    const double d2 = rel.distance2(candidate);
    if (d2 < best_d2) {
      best = candidate;
      best_d2 = d2;
    }
  }
  return best;
}

}  // namespace

int hermite_minima(const ObjectStep& a, const ObjectStep& b, double dt_s, double threshold_m,
                   PairMinimum* out) {
  double dp0[3], dv0[3], dp1[3], dv1[3];
  for (int k = 0; k < 3; ++k) {
    dp0[k] = a.p0[k] - b.p0[k];
    dv0[k] = a.v0[k] - b.v0[k];
    dp1[k] = a.p1[k] - b.p1[k];
    dv1[k] = a.v1[k] - b.v1[k];
  }
  // Bezier control points of the relative curve: the curve lies in their convex hull.
  double c0[3], c1[3], c2[3], c3[3];
  for (int k = 0; k < 3; ++k) {
    c0[k] = dp0[k];
    c1[k] = dp0[k] + dt_s * dv0[k] / 3.0;
    c2[k] = dp1[k] - dt_s * dv1[k] / 3.0;
    c3[k] = dp1[k];
  }
  // Cheap filter 1: the hull's box must reach the threshold ball around the origin.
  for (int k = 0; k < 3; ++k) {
    const double lo = std::min(std::min(c0[k], c1[k]), std::min(c2[k], c3[k]));
    const double hi = std::max(std::max(c0[k], c1[k]), std::max(c2[k], c3[k]));
    if (lo > threshold_m || hi < -threshold_m) return 0;
  }
  // Cheap filter 2: the curve stays within 3/4 max|e_i| of its chord c0 + s (c3 - c0), e_i being the
  // inner control points' offsets from the chord's own control points (the Bernstein weights of the
  // inner points sum to 3 s (1 - s) <= 3/4). A chord that never comes within threshold + that bound
  // rules the pair out.
  {
    double u[3], e1 = 0.0, e2 = 0.0;
    for (int k = 0; k < 3; ++k) u[k] = c3[k] - c0[k];
    for (int k = 0; k < 3; ++k) {
      const double o1 = c1[k] - (c0[k] + u[k] / 3.0), o2 = c2[k] - (c0[k] + 2.0 * u[k] / 3.0);
      e1 += o1 * o1;
      e2 += o2 * o2;
    }
    const double deviation = 0.75 * std::sqrt(std::max(e1, e2));
    const double uu = dot3(u, u);
    const double s = uu > 0.0 ? std::clamp(-dot3(c0, u) / uu, 0.0, 1.0) : 0.0;
    double chord2 = 0.0;
    for (int k = 0; k < 3; ++k) {
      const double w = c0[k] + s * u[k];
      chord2 += w * w;
    }
    const double reach = threshold_m + deviation;
    if (chord2 > reach * reach * (1.0 + 1e-12) + 1e-12) return 0;
  }

  RelativeCubic rel;
  for (int k = 0; k < 3; ++k) {
    rel.a0[k] = dp0[k];
    rel.a1[k] = dt_s * dv0[k];
    rel.a2[k] = 3.0 * (dp1[k] - dp0[k]) - dt_s * (2.0 * dv0[k] + dv1[k]);
    rel.a3[k] = 2.0 * (dp0[k] - dp1[k]) + dt_s * (dv0[k] + dv1[k]);
  }
  // Bernstein coefficients of f = dp . dp' (degree 3 times degree 2). The end coefficients are f at the
  // ends; they take the sign of the boundary slope itself, which the neighbouring step computes from the
  // same numbers (boundary_rule.hpp).
  double d0[3], d1[3], d2[3];
  for (int k = 0; k < 3; ++k) {
    d0[k] = dt_s * dv0[k];
    d1[k] = 3.0 * (c2[k] - c1[k]);
    d2[k] = dt_s * dv1[k];
  }
  Bernstein5 root;
  root.c[0] = dt_s * boundary_slope(a.p0, a.v0, b.p0, b.v0);
  root.c[1] = (3.0 * dot3(c1, d0) + 2.0 * dot3(c0, d1)) / 5.0;
  root.c[2] = (3.0 * dot3(c2, d0) + 6.0 * dot3(c1, d1) + dot3(c0, d2)) / 10.0;
  root.c[3] = (dot3(c3, d0) + 6.0 * dot3(c2, d1) + 3.0 * dot3(c1, d2)) / 10.0;
  root.c[4] = (2.0 * dot3(c3, d1) + 3.0 * dot3(c2, d2)) / 5.0;
  root.c[5] = dt_s * boundary_slope(a.p1, a.v1, b.p1, b.v1);

  // Isolate the negative -> non-negative transitions of f by subdivision (a Bernstein polynomial whose
  // coefficients change class at most once crosses at most once), left to right.
  struct Piece {
    double lo, hi;
    Bernstein5 f;
    int depth;
  };
  Piece stack[64];
  int top = 0;
  stack[top++] = Piece{0.0, 1.0, root, 0};
  int found = 0;
  const double threshold2 = threshold_m * threshold_m;
  while (top > 0) {
    const Piece piece = stack[--top];
    const int v = piece.f.variations();
    if (v == 0) continue;
    if (v >= 2 && piece.depth < 40 && top + 2 <= 64) {
      Piece left{piece.lo, 0.5 * (piece.lo + piece.hi), {}, piece.depth + 1};
      Piece right{left.hi, piece.hi, {}, piece.depth + 1};
      piece.f.split(left.f, right.f);
      stack[top++] = right;
      stack[top++] = left;
      continue;
    }
    if (!(piece.f.negative(0) && !piece.f.negative(5))) continue;
    const double s = refine_root(rel, piece.lo, piece.hi);
    const double d2min = rel.distance2(s);
    if (d2min <= threshold2 * (1.0 + 1e-15) && found < kMaxMinimaPerStep) {
      const double d = std::sqrt(d2min);
      if (d <= threshold_m) out[found++] = PairMinimum{s * dt_s, d};
    }
  }
  return found;
}

}  // namespace kessler
