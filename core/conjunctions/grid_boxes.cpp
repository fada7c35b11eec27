// The box pass: each object's grown box rounded outwards to floats, its chord data, whether it is
// oversized, and (with Hermite motion, when asked) its hull. A loop over arrays per pass, so that each
// vectorises.
//
// GCC 12 vectorises these loops only where floating-point operations may be assumed not to trap. No
// value changes (only exception flags could, and the core reads none); the same pragma as in
// symplectic_propagator.cpp.
#pragma GCC optimize("no-trapping-math")

#include <algorithm>
#include <cmath>

#include "core/conjunctions/broad_phase_grid.hpp"
#include "core/conjunctions/grid_boxes.hpp"

#ifdef __AVX512F__
#include <immintrin.h>
#endif

namespace kessler {
namespace {

using grid::kFarOut_m;
using grid::kOversizedFlag;

constexpr double kRoundingMargin_m = 1e-3;
// A box's float rounding is 2^-22 of its coordinates on each side (at most 1.7 m in LEO): boxes wider
// than the motion bound by more than this are far out, and oversized.
constexpr double kFarRoundingSlack_m = 100.0;

// A float below (above) a double: x moved out by 2^-22 |x| rounds to a float on the same side of x
// (rounding to nearest moves it at most 2^-24 |x| back). No branch, so the box pass still vectorises.
inline float float_below(double x) {
  return static_cast<float>(x - std::fabs(x) * 0x1p-22);
}
inline float float_above(double x) {
  return static_cast<float>(x + std::fabs(x) * 0x1p-22);
}

inline void min_max4(double a, double b, double c, double d, double& lo, double& hi) {
  lo = std::min(std::min(a, b), std::min(c, d));
  hi = std::max(std::max(a, b), std::max(c, d));
}

// The box pass's outputs, arrays per object (see grow_boxes).
struct BoxPassOutput {
  float *lo[3], *hi[3];
  float* reach;
  std::uint32_t* flags;  // grid::kChordEndsMask bits, grid::kOversizedFlag
};

// Each object's grown box rounded outwards to floats, the chord filter's direction bits and reach
// (step_chord.hpp), and whether it is oversized; `reach` is dt / 3 (Hermite: the inner control points'
// offsets dt v / 3) or dt (the line). Every pointer is a local restrict copy (read through a
// struct or a vector, the loop would reload it after each store), and the loop has no reduction (GCC
// 12 then emits it scalar in spite of reporting it vectorised): both would leave it scalar.
template <bool kHermite, bool kRadii>
void grow_boxes(const StateArrays& s0, const StateArrays& s1, const ThresholdShare& share, double reach,
                double max_motion, const BoxPassOutput& out, std::size_t begin, std::size_t end) {
  const double* __restrict x0 = s0.x.data();
  const double* __restrict y0 = s0.y.data();
  const double* __restrict z0 = s0.z.data();
  const double* __restrict vx0 = s0.vx.data();
  const double* __restrict vy0 = s0.vy.data();
  const double* __restrict vz0 = s0.vz.data();
  const double* __restrict x1 = s1.x.data();
  const double* __restrict y1 = s1.y.data();
  const double* __restrict z1 = s1.z.data();
  const double* __restrict vx1 = s1.vx.data();
  const double* __restrict vy1 = s1.vy.data();
  const double* __restrict vz1 = s1.vz.data();
  const double* __restrict radius = share.radius_m;  // null: every object's share is fixed_share
  float* __restrict lo_x = out.lo[0];
  float* __restrict lo_y = out.lo[1];
  float* __restrict lo_z = out.lo[2];
  float* __restrict hi_x = out.hi[0];
  float* __restrict hi_y = out.hi[1];
  float* __restrict hi_z = out.hi[2];
  float* __restrict reach_out = out.reach;
  std::uint32_t* __restrict flags = out.flags;
  const double kappa = share.kappa, fixed_share = share.fixed_m;
#pragma omp simd
  for (std::size_t i = begin; i < end; ++i) {
    const double grow = (kRadii ? kappa * radius[i] : fixed_share) + kRoundingMargin_m;
    const double p0[3] = {x0[i], y0[i], z0[i]};
    const double v0[3] = {vx0[i], vy0[i], vz0[i]};
    const double p1[3] = {x1[i], y1[i], z1[i]};
    const double v1[3] = {vx1[i], vy1[i], vz1[i]};
    double lo[3], hi[3], motion_edge = 0.0;
    // The chord's end, and the inner control points' offsets from the chord (step_chord.hpp).
    double chord_end[3], e1 = 0.0, e2 = 0.0;
    for (int k = 0; k < 3; ++k) {
      if constexpr (kHermite) {
        const double c1 = p0[k] + reach * v0[k], c2 = p1[k] - reach * v1[k];
        min_max4(p0[k], c1, c2, p1[k], lo[k], hi[k]);
        const double u = p1[k] - p0[k];
        const double o1 = c1 - (p0[k] + u / 3.0), o2 = c2 - (p0[k] + 2.0 * u / 3.0);
        e1 += o1 * o1;
        e2 += o2 * o2;
        chord_end[k] = p1[k];
      } else {
        chord_end[k] = p0[k] + reach * v0[k];
        lo[k] = std::min(p0[k], chord_end[k]);
        hi[k] = std::max(p0[k], chord_end[k]);
      }
      motion_edge = std::max(motion_edge, hi[k] - lo[k]);
    }
    // The chord's ends stand in for the grown box's corners nearest to them (one direction bit per
    // axis); err is the larger distance of those corners from the exact ends.
    float lo_f[3], hi_f[3];
    std::uint32_t bits = 0;
    double err0 = 0.0, err1 = 0.0, float_edge = 0.0, farthest = 0.0;
    for (int k = 0; k < 3; ++k) {
      lo_f[k] = float_below(lo[k] - grow);
      hi_f[k] = float_above(hi[k] + grow);
      float_edge = std::max(float_edge, double{hi_f[k]} - double{lo_f[k]});
      farthest = std::max(farthest, std::max(-double{lo_f[k]}, double{hi_f[k]}));
      const bool rising = p0[k] <= chord_end[k];
      bits |= rising ? 1u << k : 0u;
      const double d0 = (rising ? double{lo_f[k]} : double{hi_f[k]}) - p0[k];
      const double d1 = (rising ? double{hi_f[k]} : double{lo_f[k]}) - chord_end[k];
      err0 += d0 * d0;
      err1 += d1 * d1;
    }
    // Far out (some catalog entries sit at ~10^12 m): beyond kFarOut_m, or rounding to floats alone
    // widens the box past the bound.
    const bool oversized = !(motion_edge <= max_motion) || !(farthest <= double{kFarOut_m}) ||
                           !(float_edge <= max_motion + 2.0 * grow + kFarRoundingSlack_m) ||
                           !std::isfinite(lo[0] + lo[1] + lo[2] + hi[0] + hi[1] + hi[2] + grow);
    lo_x[i] = lo_f[0];
    lo_y[i] = lo_f[1];
    lo_z[i] = lo_f[2];
    hi_x[i] = hi_f[0];
    hi_y[i] = hi_f[1];
    hi_z[i] = hi_f[2];
    reach_out[i] = chord_reach_m(grow, e1, e2, std::sqrt(std::max(err0, err1)));
    flags[i] = bits | (oversized ? kOversizedFlag : 0u);
  }
}

// Each object's oversized flag (one byte, from the box pass's flags), and the largest box edge [m] of
// the others (the differences of the float corners taken in double): one loop that vectorises (the list
// of oversized objects is gathered after it, from the flags).
double flag_oversized(const BoxPassOutput& boxes, char* oversized_out, std::size_t begin, std::size_t end) {
  const float* __restrict lo_x = boxes.lo[0];
  const float* __restrict lo_y = boxes.lo[1];
  const float* __restrict lo_z = boxes.lo[2];
  const float* __restrict hi_x = boxes.hi[0];
  const float* __restrict hi_y = boxes.hi[1];
  const float* __restrict hi_z = boxes.hi[2];
  const std::uint32_t* __restrict flags = boxes.flags;
  char* __restrict oversized = oversized_out;
  double largest = 0.0;
#pragma omp simd reduction(max : largest)
  for (std::size_t i = begin; i < end; ++i) {
    const bool out = (flags[i] & kOversizedFlag) != 0;
    oversized[i] = out;
    const double edge =
        std::max(double{hi_x[i]} - double{lo_x[i]},
                 std::max(double{hi_y[i]} - double{lo_y[i]}, double{hi_z[i]} - double{lo_z[i]}));
    largest = std::max(largest, out ? 0.0 : edge);
  }
  return largest;
}

}  // namespace

void BroadPhaseGrid::grow_chunk_boxes(const ThreadBuild& b, NarrowPhase motion, const ThresholdShare& share,
                                      double max_motion_m) {
  const StateArrays& s0 = *b.step->start;
  const StateArrays& s1 = *b.step->end;
  const bool hermite = motion == NarrowPhase::kHermite;
  const double reach = hermite ? b.step->dt_s / 3.0 : b.step->dt_s;
  const BoxPassOutput out{{box_lo_[0].data(), box_lo_[1].data(), box_lo_[2].data()},
                          {box_hi_[0].data(), box_hi_[1].data(), box_hi_[2].data()},
                          box_reach_.data(),
                          box_flags_.data()};
  const bool radii = share.radius_m != nullptr;
  const std::size_t begin = b.begin, end = b.end;
  if (hermite) {
    radii ? grow_boxes<true, true>(s0, s1, share, reach, max_motion_m, out, begin, end)
          : grow_boxes<true, false>(s0, s1, share, reach, max_motion_m, out, begin, end);
  } else {
    radii ? grow_boxes<false, true>(s0, s1, share, reach, max_motion_m, out, begin, end)
          : grow_boxes<false, false>(s0, s1, share, reach, max_motion_m, out, begin, end);
  }
}

double BroadPhaseGrid::flag_chunk_boxes(const ThreadBuild& b) {
  // The box pass's output read back (flag_oversized takes the corners and the flags).
  const BoxPassOutput boxes{{box_lo_[0].data(), box_lo_[1].data(), box_lo_[2].data()},
                            {box_hi_[0].data(), box_hi_[1].data(), box_hi_[2].data()},
                            box_reach_.data(),
                            box_flags_.data()};
  char* const oversized_flags = oversized_flag_.data();
  const double largest_edge = flag_oversized(boxes, oversized_flags, b.begin, b.end);
  std::vector<std::uint32_t>& mine = thread_oversized_[b.t];
  mine.clear();
  for_each_flagged(oversized_flags, b.begin, b.end,
                   [&](std::size_t i) { mine.push_back(static_cast<std::uint32_t>(i)); });
  return largest_edge;
}

void BroadPhaseGrid::write_chunk_hulls(const ThreadBuild& b, const ThresholdShare& share) {
  // The hulls, in their own loop: their 64-byte stores would keep the box loop from vectorising.
  // Streaming stores: the hulls are read once, by whichever thread meets the pair, so they need not
  // pass through this core's cache (nor be fetched into it before being overwritten).
  const StateArrays& s0 = *b.step->start;
  const StateArrays& s1 = *b.step->end;
  const double dt = b.step->dt_s;
  HermiteHull* const hulls = hull_.data();
#ifdef __AVX512F__
  for (std::size_t i = b.begin; i < b.end; ++i) {
    const HermiteHull hull = hermite_hull(gather_object_step(s0, s1, i), dt, share(i));
    _mm512_stream_si512(reinterpret_cast<__m512i*>(&hulls[i]), _mm512_load_si512(&hull));
  }
  _mm_sfence();  // visible to the other threads before the barrier lets them read
#else
  for (std::size_t i = b.begin; i < b.end; ++i)
    hulls[i] = hermite_hull(gather_object_step(s0, s1, i), dt, share(i));
#endif
}

}  // namespace kessler
