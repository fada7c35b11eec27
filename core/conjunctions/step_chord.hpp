// The relative-chord filter that the broad phase runs on each pair whose boxes overlap, before the pair
// becomes a candidate: most pairs whose boxes overlap cross the common region at different times and
// are far apart at every instant (at 320,000 objects and 30 s steps, 2.4 box pairs per object and step,
// of which about 1 in 1,000 passes this filter).
//
// Each object's motion over the step, s = tau / dt in [0, 1], is a cubic Bezier curve B(s) (Hermite
// motion: control points c0 = p0, c1 = p0 + dt v0 / 3, c2 = p1 - dt v1 / 3, c3 = p1) or the paper's
// straight line from p0 to p0 + dt v0. Its chord K(s) = c0 + s (c3 - c0) is the same line raised to
// degree 3 (control points c0 + (c3 - c0) k / 3), so B(s) - K(s) is the Bezier curve with control
// points 0, e1, e2, 0, where e1 = c1 - (c0 + (c3 - c0) / 3) and e2 = c2 - (c0 + 2 (c3 - c0) / 3):
//   |B(s) - K(s)| <= 3 s (1 - s) max(|e1|, |e2|) <= 3/4 max(|e1|, |e2|) =: dev   (0 for the line).
// The filter does not store the chord: it takes the two corners of the object's grid box that the
// chord's ends are nearest to (one direction bit per axis), and err, the larger distance of those
// corners from the exact ends (the box's growth by the threshold share, its rounding to floats, and
// any bulge of the curve beyond its ends on an axis). Every point of that corner-to-corner line at s
// is then within err of K(s) (a convex combination of the ends), so within dev + err of B(s).
// For a pair, at the same s (time is kept), the relative corner line is within dev_a + err_a + dev_b +
// err_b of the relative motion. The pair can come within share_a + share_b (the threshold) only if the
// relative corner line comes within reach_a + reach_b of the origin, reach = share + dev + err.
// In LEO at 30 s, dev is ~0.9 km (gravity bends the arc by g dt^2 / 6 at the inner control points)
// and err a few metres (up to ~1 km where the motion turns on an axis), against boxes of ~200 km: the
// filter keeps pairs that are within a few km at the same moment and drops those that only share a
// region of space. Each reach is rounded up to a float, and the test, in double from the float
// corners, adds 1 mm against its own rounding: it never drops a pair the narrow phase can report
// (tests/conjunctions/step_chord_test.cpp checks it on the grid, on 60,000 random encounters). A
// looser single-precision version on 16 pairs at once runs first in the grid's walk (below).
#pragma once

#include <algorithm>
#include <cmath>

#ifdef __AVX512F__
#include <immintrin.h>
#endif

namespace kessler {

// An object's reach [m] from its threshold share, the squared norms of its inner control points'
// offsets from the chord (0 for the straight line) and err [m], rounded up to a float.
inline float chord_reach_m(double share_m, double e1_squared, double e2_squared, double err_m) {
  const double reach = share_m + 0.75 * std::sqrt(std::max(e1_squared, e2_squared)) + err_m;
  return static_cast<float>(reach + reach * 0x1p-22);
}

// False only when objects a and b, whose motions (grown by their threshold shares) are within reach_a
// and reach_b of the lines a0 -> a1 and b0 -> b1 at the same fraction of the step, cannot come within
// their threshold of each other.
// The test's allowances for its own rounding (see chords_may_come_within): an absolute margin on the
// reach [m], a relative one on its square, and one relative to |c0|^2 for the cancellation.
inline constexpr double kChordMargin_m = 1e-3;
inline constexpr double kChordRelativeSlack = 1e-9;
inline constexpr double kChordCancellationSlack = 1e-14;

inline bool chords_may_come_within(const double a0[3], const double a1[3], double reach_a, const double b0[3],
                                   const double b1[3], double reach_b) {
  double c0[3], u[3], uu = 0.0, c0u = 0.0, c0c0 = 0.0;
  for (int k = 0; k < 3; ++k) {
    c0[k] = a0[k] - b0[k];
    u[k] = (a1[k] - b1[k]) - c0[k];
    uu += u[k] * u[k];
    c0u += c0[k] * u[k];
    c0c0 += c0[k] * c0[k];
  }
  // The closest point of the relative line c0 + s u, s in [0, 1], without a division or a branch (both
  // slow here: the outcome is random): with t = s uu = clamp(-c0.u, 0, uu),
  //   uu |c0 + s u|^2 = uu |c0|^2 + 2 t c0.u + t^2.
  // (uu = 0, a relative motion of exactly nothing, keeps the pair.) The left side cancels when the line
  // passes near the origin: its rounding, a few 2^-53 uu |c0|^2, is covered by 1e-14 uu |c0|^2 on the
  // right (4e-4 m^2 for |c0| = 200 km), whatever the reaches.
  const double t = std::min(std::max(-c0u, 0.0), uu);
  const double reach = reach_a + reach_b + kChordMargin_m;
  return uu * c0c0 + t * (2.0 * c0u + t) <=
         (reach * reach * (1.0 + kChordRelativeSlack) + kChordCancellationSlack * c0c0) * uu;
}

#ifdef __AVX512F__
// chords_may_come_within on 16 pairs at once in single precision, loose enough never to drop a pair
// that the double test keeps: the walk's pre-filter (nearly every pair whose boxes overlap fails it;
// only its survivors go on to the double test). For pairs of float corners whose relative line's ends
// c0 and c1 = c0 + u are within `extent_m` (for the grid's pairs, whose boxes overlap, 3.5 cell
// edges). Its rounding: a difference of two floats is exact to 2^-24 of itself, so the computed line
// is off by at most 2^-24 (2 |c0| + |u| + |c1|) <= 2^-21 extent_m, which the reach's margin covers 3
// times over (plus 10^-5 of the reach for the reaches' own sum); uu, c0.c0, c0.u and the left side
// are each off by a few 2^-24 uu |c0|^2 (|t| <= |c0.u| <= |c0| |u|), covered 50 times over by 10^-4
// uu |c0|^2 on the right (a loosening of 1 % of |c0| in the distance: 2 km at 200 km apart). No
// overflow for extents below 10^8 m (every product below 10^34); a NaN keeps the pair.
// (GCC 12's intrinsics start some results from _mm512_undefined_*(), which -Wmaybe-uninitialized
// mistakes for a read of an uninitialised value once inlined.)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
inline __mmask16 chords_may_come_within_float(const __m512 a0[3], const __m512 a1[3], __m512 reach_a,
                                              const __m512 b0[3], const __m512 b1[3], __m512 reach_b,
                                              float extent_m) {
  constexpr float kRelativeSlack = 1e-5f, kCancellationSlack = 1e-4f;
  const float margin_m = 1e-3f + 3.0f * 0x1p-21f * extent_m;
  __m512 c0[3], u[3];
  for (int k = 0; k < 3; ++k) {
    c0[k] = _mm512_sub_ps(a0[k], b0[k]);
    u[k] = _mm512_sub_ps(_mm512_sub_ps(a1[k], b1[k]), c0[k]);
  }
  __m512 uu = _mm512_mul_ps(u[0], u[0]), c0u = _mm512_mul_ps(c0[0], u[0]), c0c0 = _mm512_mul_ps(c0[0], c0[0]);
  for (int k = 1; k < 3; ++k) {
    uu = _mm512_fmadd_ps(u[k], u[k], uu);
    c0u = _mm512_fmadd_ps(c0[k], u[k], c0u);
    c0c0 = _mm512_fmadd_ps(c0[k], c0[k], c0c0);
  }
  const __m512 zero = _mm512_setzero_ps();
  const __m512 t = _mm512_min_ps(_mm512_max_ps(_mm512_sub_ps(zero, c0u), zero), uu);
  const __m512 reach = _mm512_fmadd_ps(_mm512_add_ps(reach_a, reach_b), _mm512_set1_ps(1.0f + kRelativeSlack),
                                       _mm512_set1_ps(margin_m));
  const __m512 left =
      _mm512_fmadd_ps(uu, c0c0, _mm512_mul_ps(t, _mm512_fmadd_ps(_mm512_set1_ps(2.0f), c0u, t)));
  const __m512 right = _mm512_mul_ps(
      _mm512_fmadd_ps(reach, reach, _mm512_mul_ps(_mm512_set1_ps(kCancellationSlack), c0c0)), uu);
  return _mm512_cmp_ps_mask(left, right, _CMP_NGT_UQ);  // not greater; unordered (NaN) keeps
}
#pragma GCC diagnostic pop
#endif

}  // namespace kessler
