// GCC 12 vectorises the key pass (key_boxes: a floor and clamps per axis) only where floating-point
// operations may be assumed not to trap. No value changes (only exception flags could, and the core
// reads none); the same pragma as in symplectic_propagator.cpp.
#pragma GCC optimize("no-trapping-math")

#include "core/conjunctions/broad_phase_grid.hpp"

#include "core/integration/team_timeline.hpp"
#include "core/integration/thread_chunks.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>
#include <type_traits>

#include <omp.h>

#ifdef __AVX512F__
#include <immintrin.h>
#endif

namespace kessler {
namespace {

constexpr int kAxisBits = 21;
constexpr std::int64_t kAxisOffset = std::int64_t{1} << (kAxisBits - 1);
constexpr double kAxisLimit = static_cast<double>(kAxisOffset - 2);  // keeps neighbours in range
constexpr double kRoundingMargin_m = 1e-3;
// A box's float rounding is 2^-22 of its coordinates on each side (at most 1.7 m in LEO): boxes wider
// than the motion bound by more than this are far out, and oversized.
constexpr double kFarRoundingSlack_m = 100.0;
// Boxes reaching beyond this along any axis [m] (2.6 times the Moon's distance) are far out too, and
// oversized: rounding widens a box there by up to 240 m a side, so real catalogs' entries at ~10^12 m
// would otherwise stay in the grid with boxes hundreds of km wide and set every cell's edge. Each grid
// box lies inside the cube of this half-edge, so an oversized box that misses the cube can meet only
// other oversized boxes.
constexpr float kFarOut_m = 1.0e9f;
// The regions' histogram takes every kHistogramStride-th object; its bins span the last one's central
// 99 % widened by kHistogramMargin of that on each side.
constexpr std::size_t kHistogramStride = 4;
constexpr double kHistogramMargin = 0.125;
// Measured costs that share out the work (the regions' per slot, the passes' per object): one scan's
// weight in the smoothed cost, and the most it may differ from the team's mean (either way: a stalled
// thread, a page fault in one step, must not empty a region or a chunk).
constexpr double kCostSmoothing = 0.125;
constexpr double kCostSpread = 1.5;

// costs[0, count) each moved by kCostSmoothing towards measured(i) (set to it where still 0), then
// clamped within kCostSpread of their mean.
template <typename Measured>
void smooth_costs(double* costs, std::size_t count, Measured measured) {
  double mean = 0.0;
  for (std::size_t i = 0; i < count; ++i) {
    const double now = measured(i);
    costs[i] = costs[i] > 0.0 ? costs[i] + kCostSmoothing * (now - costs[i]) : now;
    mean += costs[i];
  }
  mean /= static_cast<double>(count);
  for (std::size_t i = 0; i < count; ++i)
    costs[i] = std::clamp(costs[i], mean / kCostSpread, mean * kCostSpread);
}
// The counting sort's coarse partitions (top bits of the bucket): at most 256.
constexpr std::size_t kMaxPartitions = 256;
// The cell edge over the largest box edge: room for the next step's boxes to grow a little, so the
// guessed cell usually fits and the keys are computed once.
constexpr double kCellMargin = 0.005;
// A guessed cell more than this factor above what the step asks for is shrunk.
constexpr double kCellShrinkRatio = 1.05;
// Coarser cells where the population is sparse: the cell grows by kCoarseningStep a build while the
// last build held fewer than kSparseObjectsPerCell objects per occupied cell, and shrinks back (never
// below the largest box) above kDenseObjectsPerCell. The walk's cost per object is a few neighbour-row
// lookups plus 16-lane box tests over the rows' slots, so a cell holding one or two objects pays the
// lookups for almost no tests. Measured on one thread (leo-19647, kappa 10): the walk at dt 30 s took
// 1.27 ms a step with 1.4 objects per cell (253 km), 0.79 with ~6 (3-4x the edge); at dt 10 s 0.73 ms
// with 1.1 (84 km), 0.44 with ~6 (9x); 320,000 objects (5.3 per cell at the box edge) were slower
// with any larger cell.
constexpr double kSparseObjectsPerCell = 4.0, kDenseObjectsPerCell = 8.0;
constexpr double kCoarseningStep = 1.25, kMaxCoarsening = 16.0;
// With several regions, each keeps at least this many cell columns (the borders fall on column edges:
// fewer columns would balance the threads badly).
constexpr double kMinColumnsPerRegion = 4.0;
// The walk's float pre-filter of the chord test runs on cells up to this edge [m] (the detector's are
// at most the 20,000 km domain): in larger ones its products could overflow.
constexpr double kFloatFilterMaxCell_m = 2.5e7;

// The coarsening for the next build, after a build whose sort put `slots` objects in `occupied` cells.
double next_coarsening(double coarsening, std::size_t slots, std::size_t occupied) {
  if (occupied == 0) return coarsening;
  const double per_cell = static_cast<double>(slots) / static_cast<double>(occupied);
  if (per_cell < kSparseObjectsPerCell) return std::min(coarsening * kCoarseningStep, kMaxCoarsening);
  if (per_cell > kDenseObjectsPerCell) return std::max(coarsening / kCoarseningStep, 1.0);
  return coarsening;
}

// Cell index along one axis, clamped (clamping keeps neighbours neighbours; NaN goes to the edge).
inline std::uint64_t axis_cell(double coordinate_m, double inverse_cell_m) {
  double q = std::floor(coordinate_m * inverse_cell_m);
  if (!(q >= -kAxisLimit)) q = -kAxisLimit;
  if (!(q <= kAxisLimit)) q = kAxisLimit;
  return static_cast<std::uint64_t>(static_cast<std::int64_t>(q) + kAxisOffset);
}

// Key offset of the row (dx, dy) (z unchanged).
constexpr std::uint64_t row_offset(int dx, int dy) {
  return static_cast<std::uint64_t>((std::int64_t{dx} << (2 * kAxisBits)) + (std::int64_t{dy} << kAxisBits));
}

// The forward half of the 26 neighbours: (0, 0, +1) in the cell's own row, and z cells -1..+1 of the
// rows (0, +1), (+1, -1), (+1, 0), (+1, +1). With the cell itself, each unordered pair of neighbouring
// cells is visited once.
constexpr std::uint64_t kForwardRows[4] = {row_offset(0, 1), row_offset(1, -1), row_offset(1, 0),
                                           row_offset(1, 1)};
// The axes a box must cross into the next cell on for each forward row to hold an overlapping box
// (bit 0: x, bit 1: y).
constexpr std::uint32_t kForwardRowNeeds[4] = {2u, 1u, 1u, 3u};

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
  std::uint32_t* flags;  // bits 0-2: the chord's direction per axis; kOversizedFlag
};
constexpr std::uint32_t kChordEndsMask = 7u;
constexpr std::uint32_t kOversizedFlag = 8u;

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

// The borders [m] of `regions` regions along x that hold shares of a histogram's objects (`bins` bins of
// `width` from `origin`) in proportion to `shares` (one per region), each border placed inside its bin as
// if the bin's objects were spread evenly across it. An empty histogram spreads the borders evenly over
// its range.
void region_borders_m(const std::uint32_t* hist, std::size_t bins, double origin, double width,
                      std::size_t regions, const double* shares, double* borders_m) {
  double total = 0.0;
  for (std::size_t b = 0; b < bins; ++b) total += hist[b];
  // Border k goes after the objects of the regions below it: their shares' part of the total.
  double all_shares = 0.0;
  for (std::size_t r = 0; r < regions; ++r) all_shares += shares[r];
  std::size_t border = 1;
  if (total > 0.0) {
    double shares_below = shares[0];  // of the regions below the next border
    double target = total * shares_below / all_shares;
    double below = 0.0;
    for (std::size_t b = 0; b < bins && border < regions; ++b) {
      const double in_bin = hist[b];
      while (border < regions && below + in_bin >= target) {
        const double fraction = in_bin > 0.0 ? (target - below) / in_bin : 0.0;
        borders_m[border++ - 1] = origin + (static_cast<double>(b) + fraction) * width;
        if (border < regions) {
          shares_below += shares[border - 1];
          target = total * shares_below / all_shares;
        }
      }
      below += in_bin;
    }
  }
  for (; border < regions; ++border)
    borders_m[border - 1] = origin + static_cast<double>(bins) * width * static_cast<double>(border) /
                                         static_cast<double>(regions);
}

// A histogram's bins for the next build: the range of the last one's central 99 % (0.5 % of the objects
// may lie beyond any bound: objects far out, on escape orbits or diverging, would otherwise stretch the
// bins until all others share one), widened by an eighth on each side, and twice as wide on a side
// whose end bin holds more (objects clamped there). Unchanged when the last one is empty.
void histogram_bins_m(const std::uint32_t* hist, std::size_t bins, double origin, double width,
                      double& next_origin, double& next_width) {
  double total = 0.0;
  for (std::size_t b = 0; b < bins; ++b) total += hist[b];
  if (!(total > 0.0)) return;
  const double tail = 0.005 * total;
  std::size_t low = 0, high = bins - 1;
  for (double below = 0.0; low + 1 < bins && below + hist[low] <= tail; ++low) below += hist[low];
  for (double above = 0.0; high > low && above + hist[high] <= tail; --high) above += hist[high];
  double lo = origin + static_cast<double>(low) * width, hi = origin + static_cast<double>(high + 1) * width;
  const double span = hi - lo;
  if (low == 0) lo -= span;
  if (high == bins - 1) hi += span;
  const double margin = kHistogramMargin * (hi - lo);
  next_origin = lo - margin;
  next_width = (hi - lo + 2.0 * margin) / static_cast<double>(bins);
}

// Each object's oversized flag (one byte, from the box pass's flags), and the largest box edge [m] of
// the others (the differences of the float corners taken in double): one loop that vectorises, where
// the scalar one with the oversized objects' list inside took 2.3 ns per object-step.
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

// The extent histogram's bins: bin 0 holds |corner| below kExtentFirst_m, bin b > 0 up to
// kExtentFirst_m 2^(b / 4), the last one everything beyond.
constexpr double kExtentFirst_m = 1.0e3;
constexpr double kExtentTail = 0.005;
inline std::size_t extent_bin(float r_m) {
  if (!(r_m >= kExtentFirst_m)) return 0;
  const double b = 1.0 + std::floor(4.0 * std::log2(r_m / kExtentFirst_m));
  return b >= 63.0 ? 63 : static_cast<std::size_t>(b);
}
inline double extent_bin_top_m(std::size_t b) {
  return kExtentFirst_m * std::exp2(0.25 * static_cast<double>(b));
}

// counts[0, size) replaced by their running sum from `first` (the sum of those before each, plus first).
// With AVX-512, 16 at a time (a scan in a register: 4 shifted adds), where the one-at-a-time loop's
// chain of dependent adds took ~6 % of the build; the sort's partitions hold a multiple of 64 buckets,
// so the scalar loop after it only serves other machines.
void exclusive_prefix_sum(std::uint32_t* counts, std::size_t size, std::uint32_t first) {
  std::size_t f = 0;
#ifdef __AVX512F__
  const __m512i zero = _mm512_setzero_si512(), last = _mm512_set1_epi32(15);
  __m512i carry = _mm512_set1_epi32(static_cast<int>(first));
  for (; f + 16 <= size; f += 16) {
    const __m512i c = _mm512_loadu_si512(counts + f);
    __m512i sum = _mm512_add_epi32(c, _mm512_alignr_epi32(c, zero, 15));  // + the lane below
    sum = _mm512_add_epi32(sum, _mm512_alignr_epi32(sum, zero, 14));      // + the 2 below those
    sum = _mm512_add_epi32(sum, _mm512_alignr_epi32(sum, zero, 12));
    sum = _mm512_add_epi32(sum, _mm512_alignr_epi32(sum, zero, 8));
    _mm512_storeu_si512(counts + f, _mm512_add_epi32(carry, _mm512_sub_epi32(sum, c)));
    carry = _mm512_add_epi32(carry, _mm512_permutexvar_epi32(last, sum));
  }
  first = static_cast<std::uint32_t>(_mm_cvtsi128_si32(_mm512_castsi512_si128(carry)));
#endif
  for (; f < size; ++f) {
    const std::uint32_t c = counts[f];
    counts[f] = first;
    first += c;
  }
}

}  // namespace

void BroadPhaseGrid::prepare(std::size_t n, int threads) {
  box_key_.resize(n);
  box_bucket_.resize(n);
  box_crosses_.resize(n);
  for (auto& axis : box_lo_) axis.resize(n);
  for (auto& axis : box_hi_) axis.resize(n);
  box_reach_.resize(n);
  box_flags_.resize(n);
  hull_.resize(n);
  oversized_flag_.resize(n);
  scratch_.resize(2 * n);
  ensure_slot_capacity(n);
  // One region per thread (at most kMaxRegions). At least 2 buckets per object in all, a power of two
  // per region: occupied cells hold 4-8 objects where the coarsening can reach that (load ~1/16), and
  // one object at worst (load <= 1/2); the occupancy bitmap makes empty buckets cheap. Each step the
  // sort clears, counts and sums the whole table: with 4 buckets per object, 320,000 objects spent
  // 5 % more (an 8 MB table that the cache did not hold), 20,000 and the catalogs 1-4 %.
  // Up to 256 coarse partitions for the sort, each of at least 64 buckets.
  const std::size_t team = static_cast<std::size_t>(std::max(threads, 1));
  regions_ = std::min(requested_regions_ > 0 ? requested_regions_ : team, kMaxRegions);
  std::size_t region_buckets = 64;
  int bits = 6;
  while (regions_ * region_buckets < 2 * n) {
    region_buckets *= 2;
    ++bits;
  }
  region_bits_ = bits;
  region_mask_ = region_buckets - 1;
  const std::size_t buckets = regions_ * region_buckets;
  if (buckets > std::size_t{kBucketMask} + 1)
    throw std::length_error("conjunction grid: " + std::to_string(n) +
                            " objects are more than its buckets can key");
  // Each thread scatters its chunk into every partition: with fewer than ~32 objects per thread and
  // partition, threads would write the same cache lines (a 16-thread team on 20,000 objects and 256
  // partitions measured no speed-up at all in the scatter). So partitions <= n / (32 threads).
  int region_partition_bits = 0;
  while (region_partition_bits < bits - 6 && (regions_ << (region_partition_bits + 1)) <= kMaxPartitions &&
         (regions_ << (region_partition_bits + 1)) * 32 * team <= n)
    ++region_partition_bits;
  partitions_ = regions_ << region_partition_bits;
  fine_bits_ = bits - region_partition_bits;
  const std::size_t partitions = partitions_;
  bucket_start_.resize(buckets + 1);
  occupied_.resize(buckets / 64);
  coarse_count_.resize(team * partitions);
  group_start_.resize(team * partitions);
  thread_oversized_.resize(team);
  thread_edge_.resize(team);
  thread_occupied_.resize(team);
  thread_sort_s_.resize(team);
  thread_pass_.resize(team);
  if (regions_ != costed_regions_) {  // costs measured for other regions say nothing of these
    std::fill(std::begin(cost_per_slot_s_), std::end(cost_per_slot_s_), 0.0);
    costed_regions_ = regions_;
  }
  occupancy_team_ = std::min(occupancy_team_, team);
  partition_start_.resize(partitions);
  thread_bucket_cursor_.resize(team);
  for (auto& cursor : thread_bucket_cursor_) cursor.resize(std::size_t{1} << fine_bits_);
  hist_.resize(kHistogramBins);
  thread_hist_.resize(team * kHistogramBins);
  thread_extent_hist_.resize(team * kExtentBins);
  prepared_threads_ = team;
}

void BroadPhaseGrid::ensure_slot_capacity(std::size_t slots) {
  if (slots <= slot_capacity_) return;
  // Room for ghosts beyond the objects (about 1 % of them with 2 threads, more with more regions), so
  // that the arrays seldom grow again.
  slot_capacity_ = slots + slots / 8;
  for (auto& axis : slot_box_) axis.resize(slot_capacity_ + kLanes);
  slot_chord_.resize(slot_capacity_ + kLanes);
  slot_key_.resize(slot_capacity_);
  slot_crosses_.resize(slot_capacity_);
  slot_index_.resize(slot_capacity_);
}

void BroadPhaseGrid::build(const StepEnds& step, NarrowPhase motion, const ThresholdShare& share,
                           double max_motion_m, bool with_hulls) {
  const std::size_t n = step.start->size();
  const int threads = n >= kParallelMinimumObjects ? omp_get_max_threads() : 1;
  prepare(n, threads);
  TeamTimeline& timeline = detector_timeline();
  timeline.region_start(static_cast<std::size_t>(threads));
#pragma omp parallel num_threads(threads)
  {
    timeline.enter(static_cast<std::size_t>(omp_get_thread_num()));
    build_in_team(step, motion, share, max_motion_m, with_hulls);
  }
  timeline.region_end();
}

void BroadPhaseGrid::build_in_team(const StepEnds& step, NarrowPhase motion, const ThresholdShare& share,
                                   double max_motion_m, bool with_hulls) {
  const StateArrays& s0 = *step.start;
  const StateArrays& s1 = *step.end;
  const std::size_t n = s0.size();
  const double dt = step.dt_s;
  const bool hermite = motion == NarrowPhase::kHermite;
  const std::size_t partitions = partitions_;
  const std::size_t fine_buckets = std::size_t{1} << fine_bits_;
  const std::size_t regions = regions_;
  const std::size_t buckets = regions << region_bits_;
  const std::size_t threads = static_cast<std::size_t>(omp_get_num_threads());
  const std::size_t t = static_cast<std::size_t>(omp_get_thread_num());
  if (threads > prepared_threads_) throw std::logic_error("BroadPhaseGrid: team larger than prepared");
  // Each thread owns the chunk of objects whose end states the propagator wrote on this core
  // (thread_chunks.hpp), so the first pass reads what this core holds; its borders moved by the
  // threads' measured costs (pass_chunk).
  const auto [begin, end] = pass_chunk(step.chunks, n, t, threads);
  const double pass_start_s = omp_get_wtime();
  // The cell edges guessed from the last step (read by every thread before anyone may change them):
  // along y and z, and the columns' along x (no larger).
  const double guess = next_cell_m_, guess_column = next_column_m_;
  const double extent_m = next_extent_m_;
  // Read before the first barrier: a thread that reads it later may find it grown by another.
  const std::size_t slot_capacity = slot_capacity_;
  std::uint32_t* counts = &coarse_count_[t * partitions];
  std::vector<std::uint32_t>& my_oversized = thread_oversized_[t];

  // The regions' borders along x [m]: from the last build's histogram (a build that keys again after
  // the barrier takes them from its own, below: the first one has no other). Every thread computes the
  // same borders and cell columns itself, so no thread waits for them.
  RegionMap map;
  map.region_bits = region_bits_;
  std::fill(std::begin(map.first_column), std::end(map.first_column), ~std::uint32_t{0});
  double borders_m[kMaxRegions - 1];
  double bin_origin = kDefaultBinOrigin_m, bin_width = kDefaultBinWidth_m;  // this build's histogram's
  // Each region's share of the objects: inverse to its cost per slot so far (record_region_costs).
  double shares[kMaxRegions];
  for (std::size_t r = 0; r < regions; ++r)
    shares[r] = cost_per_slot_s_[r] > 0.0 ? 1.0 / cost_per_slot_s_[r] : 1.0;
  if (regions > 1) {
    region_borders_m(hist_.data(), kHistogramBins, hist_origin_m_, hist_width_m_, regions, shares, borders_m);
    histogram_bins_m(hist_.data(), kHistogramBins, hist_origin_m_, hist_width_m_, bin_origin, bin_width);
  }

  // Cell keys, the crossing bits and the coarse counts of this thread's chunk for cells `column` wide
  // along x and `cell` along y and z.
  // The counts go to the shared array once, at the end: every thread reads all of them after the
  // barrier, so counting in place would pull the line back from other cores at each object (16 threads
  // on 19,647 objects spent 3x longer here than one thread's share).
  auto key_chunk = [&](double column, double cell) {
    const double inverse_column = 1.0 / column;
    // Each region starts at the column edge nearest its border.
    for (std::size_t s = 0; s + 1 < regions; ++s)
      map.first_column[s] =
          static_cast<std::uint32_t>(axis_cell(borders_m[s] + 0.5 * column, inverse_column));
    map.order = cell_order(extent_m, column, cell, map);
    if (map.order.in_order())
      key_boxes<true>(inverse_column, 1.0 / cell, map.order, begin, end);
    else
      key_boxes<false>(inverse_column, 1.0 / cell, map.order, begin, end);
    // The borders the region pass compares with: one with two regions (2 threads), else all.
    if (regions == 2)
      add_regions<1>(map, begin, end);
    else if (regions > 2)
      add_regions<kMaxRegions - 1>(map, begin, end);
    std::uint32_t local_counts[kMaxPartitions] = {};
    for (std::size_t i = begin; i < end; ++i) {
      if (oversized_flag_[i]) continue;
      const std::uint32_t bucket = box_bucket_[i];
      ++local_counts[(bucket & kBucketMask) >> fine_bits_];
      if (bucket > kBucketMask) ++local_counts[ghost_bucket(bucket) >> fine_bits_];  // ~1 % (2 regions)
    }
    std::copy(local_counts, local_counts + partitions, counts);
  };

  // Pass 1: grown boxes, the chord filter's data, the oversized objects and the largest edge (in its own
  // function, on plain arrays, so that it vectorises), then (with the guessed cell) keys.
  const double reach = hermite ? dt / 3.0 : dt;
  const BoxPassOutput out{{box_lo_[0].data(), box_lo_[1].data(), box_lo_[2].data()},
                          {box_hi_[0].data(), box_hi_[1].data(), box_hi_[2].data()},
                          box_reach_.data(),
                          box_flags_.data()};
  const bool radii = share.radius_m != nullptr;
  if (hermite) {
    radii ? grow_boxes<true, true>(s0, s1, share, reach, max_motion_m, out, begin, end)
          : grow_boxes<true, false>(s0, s1, share, reach, max_motion_m, out, begin, end);
  } else {
    radii ? grow_boxes<false, true>(s0, s1, share, reach, max_motion_m, out, begin, end)
          : grow_boxes<false, false>(s0, s1, share, reach, max_motion_m, out, begin, end);
  }
  TeamTimeline& timeline = detector_timeline();
  timeline.mark(t, kDetGrow);
  // The oversized objects, and the largest edge of the others.
  HermiteHull* const hulls = hull_.data();
  char* const oversized_flags = oversized_flag_.data();
  const double largest_edge = flag_oversized(out, oversized_flags, begin, end);
  my_oversized.clear();
  for_each_flagged(oversized_flags, begin, end,
                   [&](std::size_t i) { my_oversized.push_back(static_cast<std::uint32_t>(i)); });
  {
    // How far the population spreads (for the next build's cell order): |lower corner| of every
    // kExtentStride-th object, binned by powers of 2^(1/4) from kExtentFirst_m.
    std::uint32_t local_hist[kExtentBins] = {};
    for (std::size_t i = begin; i < end; i += kExtentStride) {
      if (oversized_flags[i]) continue;
      const float r =
          std::max(std::fabs(box_lo_[0][i]), std::max(std::fabs(box_lo_[1][i]), std::fabs(box_lo_[2][i])));
      ++local_hist[extent_bin(r)];
    }
    std::copy(local_hist, local_hist + kExtentBins, &thread_extent_hist_[t * kExtentBins]);
  }
  if (regions > 1) {
    // The histogram of the lower x corners for the regions' borders, on every kHistogramStride-th
    // object (the borders only balance the threads' work: no result depends on them).
    std::uint32_t local_hist[kHistogramBins] = {};
    const double inverse_bin = 1.0 / bin_width;
    for (std::size_t i = begin; i < end; i += kHistogramStride) {
      if (oversized_flags[i]) continue;
      const float x = box_lo_[0][i];
      const double q = (x - bin_origin) * inverse_bin;
      ++local_hist[q <= 0.0 ? 0 : q >= kHistogramBins - 1 ? kHistogramBins - 1 : static_cast<std::size_t>(q)];
    }
    std::copy(local_hist, local_hist + kHistogramBins, &thread_hist_[t * kHistogramBins]);
  }
  if (hermite && with_hulls) {
    // The hulls, in their own loop: their 64-byte stores would keep the box loop from vectorising.
    // Streaming stores: the hulls are read once, by whichever thread meets the pair, so they need not
    // pass through this core's cache (nor be fetched into it before being overwritten).
#ifdef __AVX512F__
    for (std::size_t i = begin; i < end; ++i) {
      const HermiteHull hull = hermite_hull(gather_object_step(s0, s1, i), dt, share(i));
      _mm512_stream_si512(reinterpret_cast<__m512i*>(&hulls[i]), _mm512_load_si512(&hull));
    }
    _mm_sfence();  // visible to the other threads before the barrier lets them read
#else
    for (std::size_t i = begin; i < end; ++i)
      hulls[i] = hermite_hull(gather_object_step(s0, s1, i), dt, share(i));
#endif
  }
  thread_edge_[t] = largest_edge;
  timeline.mark(t, kDetEdges);

  // Coarse scatter of this thread's boxes into its own part of scratch_, [2 begin, 2 end), grouped by
  // partition: whole records, read back in sequence by the partition's sorter. It needs this chunk's
  // counts alone, so it runs before the barrier.
  auto scatter_chunk = [&] {
    std::uint32_t at = static_cast<std::uint32_t>(2 * begin);
    std::uint32_t* group = &group_start_[t * partitions];
    std::uint32_t cursor[kMaxPartitions];
    for (std::size_t p = 0; p < partitions; ++p) {
      group[p] = cursor[p] = at;
      at += counts[p];
    }
    // Whole records, built in registers from the passes' arrays (read in sequence) and stored in one
    // go: stored field by field, into lines that the other cores read in the last sort, 2 threads took
    // twice as long here (the store queue fills while those lines are fetched back). With a team, the
    // line a record kAhead objects on goes to is asked for ahead, for writing, so those fetches overlap
    // (2 threads: 67 -> 54 ms a thread for leo-19647's quarter day; one thread, whose lines are its
    // own, only pays for the extra instructions).
    auto scatter = [&](auto ask_ahead) {
      constexpr std::size_t kAhead = 16;
      for (std::size_t i = begin; i < end; ++i) {
        if constexpr (decltype(ask_ahead)::value) {
          if (i + kAhead < end) {
            const char* line = reinterpret_cast<const char*>(
                &scratch_[cursor[(box_bucket_[i + kAhead] & kBucketMask) >> fine_bits_]]);
            __builtin_prefetch(line, 1);
            __builtin_prefetch(line + sizeof(GridBox), 1);  // a record may straddle two lines
          }
        }
        if (oversized_flag_[i]) continue;
        GridBox box;
        for (int k = 0; k < 3; ++k) {
          box.lo[k] = box_lo_[k][i];
          box.hi[k] = box_hi_[k][i];
        }
        const std::uint32_t crosses = box_crosses_[i], bucket = box_bucket_[i];
        box.index = static_cast<std::uint32_t>(i);
        box.key = box_key_[i];
        box.chord = chord_word(box_reach_[i], box_flags_[i] & kChordEndsMask);
        if (bucket > kBucketMask) {  // ghosted: about 1 % of the boxes with 2 regions
          box.crosses = crosses | kGhost;
          box.bucket = ghost_bucket(bucket);
          scratch_[cursor[box.bucket >> fine_bits_]++] = box;
          box.crosses = crosses & ~kCrossesX;
        } else {
          box.crosses = crosses;
        }
        box.bucket = bucket & kBucketMask;
        scratch_[cursor[box.bucket >> fine_bits_]++] = box;
      }
    };
    if (threads > 1)
      scatter(std::true_type{});
    else
      scatter(std::false_type{});
  };
  // Whether boxes no larger than edge fit the guessed cell (1e-9: rounding of the keys).
  auto fit_guess = [&](double edge) {
    return guess > 0.0 && edge * (1.0 + 1e-9) <= std::min(guess, guess_column);
  };
  // With the guessed cell, when this chunk's boxes fit it: keys, then the scatter (a chunk that does not
  // fit means that every thread keys again after the barrier).
  const bool own_fits = fit_guess(largest_edge);
  if (own_fits) key_chunk(guess_column, guess);
  timeline.mark(t, kDetKeys);
  if (own_fits) scatter_chunk();
  timeline.mark(t, kDetScatter);
  if (t == 0) {
    // Before the barrier, what depends on the last build alone (the sorts after it change both).
    // The coarsening follows the last build's objects per occupied cell.
    std::size_t occupied = 0;
    for (std::size_t u = 0; u < occupancy_team_; ++u) occupied += thread_occupied_[u];
    occupancy_team_ = threads;
    coarsening_ = next_coarsening(coarsening_, slots_in_grid_, occupied);
    for (std::size_t r = 0; r < regions; ++r) region_progress_[r].count.store(0, std::memory_order_relaxed);
    layout_ready_->count.store(0, std::memory_order_relaxed);
  }
  double pass_s = omp_get_wtime() - pass_start_s;  // the passes over this thread's chunk
#pragma omp barrier
  timeline.mark(t, kDetWait);
  // Every thread takes the same maximum over the chunks (exact: no order dependence).
  double largest = 0.0;
  for (std::size_t u = 0; u < threads; ++u) largest = std::max(largest, thread_edge_[u]);
  double cell = guess, column = guess_column;
  const bool fits = fit_guess(largest);
  // Bin b of this build's histogram, over all threads' chunks.
  auto summed_bin = [&](std::size_t b) {
    std::uint32_t total = 0;
    for (std::size_t u = 0; u < threads; ++u) total += thread_hist_[u * kHistogramBins + b];
    return total;
  };
  if (!fits) {
    // The guess is too small (or there is none): key and scatter again with a cell of this step's
    // largest edge.
    const double rekey_start_s = omp_get_wtime();
    cell = column = std::max(largest, 1.0) * (1.0 + kCellMargin);
    if (regions > 1) {
      // The borders from this build's histogram, all threads' (rare: only the first build needs it).
      std::uint32_t hist[kHistogramBins];
      for (std::size_t b = 0; b < kHistogramBins; ++b) hist[b] = summed_bin(b);
      region_borders_m(hist, kHistogramBins, bin_origin, bin_width, regions, shares, borders_m);
    }
    key_chunk(column, cell);
    scatter_chunk();
    pass_s += omp_get_wtime() - rekey_start_s;
#pragma omp barrier
  }
  thread_pass_[t] = ThreadPass{pass_s, end - begin};
  if (regions > 1) {
    // This build's histogram, summed over the threads for the next build's borders: a slice of the bins
    // each (every thread has read the last one by now).
    for (std::size_t b = kHistogramBins * t / threads; b < kHistogramBins * (t + 1) / threads; ++b)
      hist_[b] = summed_bin(b);
  }

  // Slots: partitions in order, inside a partition the threads' groups in thread order (so population
  // order within each bucket, whatever the thread count). Every thread reads all counts and computes
  // the layout itself (no serial section).
  const auto [p_begin, p_end] = partition_run(t, threads);
  std::uint32_t total_slots = 0;  // objects in the grid and ghosts
  for (std::size_t p = 0; p < partitions; ++p) {
    if (p >= p_begin && p < p_end) {  // each thread writes its own
      partition_start_[p] = total_slots;
      // The partition's first bucket start, before any sort: the walk of the region below it reads it
      // as the end of its last bucket, and may begin before this partition is sorted (once every
      // thread has counted itself in layout_ready_ below).
      bucket_start_[p * fine_buckets] = total_slots;
    }
    for (std::size_t u = 0; u < threads; ++u) total_slots += coarse_count_[u * partitions + p];
  }
  if (t + 1 == threads) bucket_start_[buckets] = total_slots;
  layout_ready_->count.fetch_add(1, std::memory_order_release);
  if (total_slots > slot_capacity) {
    // More ghosts than the arrays have room for (every thread sees the same total and capacity, so all
    // of them come here): nobody reads or writes the arrays until the sort below.
#pragma omp single
    ensure_slot_capacity(total_slots);
  }
  if (t == 0) {
    cell_size_m_ = cell;
    column_width_m_ = column;
    cell_order_ = map.order;  // the final keys'
    {
      // The next build's extent: twice the radius (largest |corner| coordinate) that holds all but
      // kExtentTail of the sampled objects.
      std::uint32_t bins[kExtentBins] = {}, total = 0, cumulative = 0;
      for (std::size_t u = 0; u < threads; ++u)
        for (std::size_t b = 0; b < kExtentBins; ++b) bins[b] += thread_extent_hist_[u * kExtentBins + b];
      for (std::size_t b = 0; b < kExtentBins; ++b) total += bins[b];
      for (std::size_t b = 0; b < kExtentBins && total > 0; ++b) {
        cumulative += bins[b];
        if (cumulative >= (1.0 - kExtentTail) * total) {
          next_extent_m_ = 2.0 * extent_bin_top_m(b);
          break;
        }
      }
    }
    ++builds_;
    if (!fits) ++rekeyed_builds_;
    slots_in_grid_ = total_slots;
    oversized_.clear();  // in population order (the chunks are in order)
    for (std::size_t u = 0; u < threads; ++u)
      oversized_.insert(oversized_.end(), thread_oversized_[u].begin(), thread_oversized_[u].end());
    // Next step's guess: the largest box edge times the coarsening (this step's cell while that fits
    // and is not much larger; the coarsening was set before the barrier).
    const double needed = std::max(largest, 1.0) * (1.0 + kCellMargin);
    const double wanted = needed * coarsening_;
    // With several regions the columns stay narrow enough for each region to keep a few (the borders
    // fall on column edges), and only y and z coarsen past that: the cells' volume, and so the objects
    // per cell the walk wants, no longer shrinks as the team grows (at 16 threads, leo-19647's cells
    // were held at the largest box edge, 1.4 objects each, and the walk took 1.9x one thread's share).
    double wanted_column = wanted;
    if (regions > 1) {
      // The central 99 % of the lower x corners, from this build's bins (histogram_bins_m).
      const double span_m = static_cast<double>(kHistogramBins) * bin_width / (1.0 + 2.0 * kHistogramMargin);
      wanted_column =
          std::min(wanted, std::max(needed, span_m / (kMinColumnsPerRegion * static_cast<double>(regions))));
    }
    auto keep_or = [&](double now, double target) {
      return (fits && now >= target && now <= target * kCellShrinkRatio) ? now : target;
    };
    next_cell_m_ = keep_or(cell, wanted);
    next_column_m_ = keep_or(column, wanted_column);
    if (regions > 1) {
      hist_origin_m_ = bin_origin;  // the bins this build's histogram is made of
      hist_width_m_ = bin_width;
    }
    // The walks may begin (slots_sorted): the cells, slot count and oversized list are set.
    layout_ready_->count.fetch_add(1, std::memory_order_release);
  }
  timeline.mark(t, kDetLayout);
  const double sort_start_s = omp_get_wtime();
  // Each thread sorts a contiguous run of partitions by fine bucket (stable), so the slot arrays'
  // lines are written by one thread each (no line shared but at the run's two ends).
  for (std::size_t p = p_begin; p < p_end; ++p) {
    if (threads > 1 && p + 1 < p_end) {
      // The next partition's records from the other threads, asked for while this one is sorted: they
      // sit in other cores' caches, and a group is too short for the hardware's stream prefetch.
      for (std::size_t u = 0; u < threads; ++u) {
        if (u == t) continue;
        const char* first = reinterpret_cast<const char*>(&scratch_[group_start_[u * partitions + p + 1]]);
        const std::size_t bytes = coarse_count_[u * partitions + p + 1] * sizeof(GridBox);
        for (std::size_t at = 0; at < bytes; at += 64) __builtin_prefetch(first + at);
      }
    }
    const std::size_t first_bucket = p * fine_buckets;
    std::uint32_t* const starts = &bucket_start_[first_bucket];
    std::uint32_t* const cursor = thread_bucket_cursor_[t].data();
    std::fill(cursor, cursor + fine_buckets, 0u);
    std::fill(&occupied_[first_bucket / 64], &occupied_[first_bucket / 64] + fine_buckets / 64, 0ull);
    // The partition's boxes: every thread's group, in thread order.
    auto each_box = [&](auto&& f) {
      for (std::size_t u = 0; u < threads; ++u) {
        const GridBox* group = &scratch_[group_start_[u * partitions + p]];
        const std::uint32_t count = coarse_count_[u * partitions + p];
        for (std::uint32_t m = 0; m < count; ++m) f(group[m]);
      }
    };
    each_box([&](const GridBox& box) {
      const std::size_t b = box.bucket;
      ++cursor[b - first_bucket];
      occupied_[b >> 6] |= std::uint64_t{1} << (b & 63);
    });
    exclusive_prefix_sum(cursor, fine_buckets, partition_start_[p]);
    // The starts (the first one is set already), then the scatter with the cursors.
    std::copy(cursor + 1, cursor + fine_buckets, starts + 1);
    each_box([&](const GridBox& box) {
      const std::uint32_t k = cursor[box.bucket - first_bucket]++;
      for (int axis = 0; axis < 3; ++axis) {
        slot_box_[axis][k] = box.lo[axis];
        slot_box_[3 + axis][k] = box.hi[axis];
      }
      slot_key_[k] = box.key;
      slot_crosses_[k] = static_cast<std::uint8_t>(box.crosses);
      slot_index_[k] = box.index;
      slot_chord_[k] = box.chord;
    });
    // Its region's walks may read it now (once the region's other partitions are sorted too).
    region_progress_[region_of_partition(p)].count.fetch_add(1, std::memory_order_release);
  }
  {
    // The occupied cells (buckets) of this thread's partitions, for the next build's cell.
    std::uint32_t occupied = 0;
    for (std::size_t w = p_begin * fine_buckets / 64; w < p_end * fine_buckets / 64; ++w)
      occupied += static_cast<std::uint32_t>(std::popcount(occupied_[w]));
    thread_occupied_[t] = occupied;
  }
  thread_sort_s_[t] = omp_get_wtime() - sort_start_s;
  timeline.mark(t, kDetSort);
}

BroadPhaseGrid::CellOrder BroadPhaseGrid::cell_order(double extent_m, double column_m, double cell_m,
                                                     const RegionMap& regions) const {
  const double region_buckets = static_cast<double>(region_mask_ + 1);
  const double cells_yz = std::ceil(extent_m / cell_m) + 2.0;
  if (!(cells_yz * cells_yz <= region_buckets)) return {};
  // The widest region's columns (the borders' columns, within the extent's).
  const double inverse_column = 1.0 / column_m;
  const std::uint64_t first = axis_cell(-0.5 * extent_m, inverse_column),
                      last = axis_cell(0.5 * extent_m, inverse_column) + 1;
  std::uint64_t widest = 0, from = first;
  for (std::size_t s = 0; s + 1 < regions_; ++s) {
    const std::uint64_t to = std::clamp<std::uint64_t>(regions.first_column[s], from, last);
    widest = std::max(widest, to - from);
    from = to;
  }
  widest = std::max(widest, last - from) + 2;
  if (!(static_cast<double>(widest) * cells_yz * cells_yz <= region_buckets)) return {};
  const auto row = static_cast<std::uint64_t>(cells_yz);
  const std::uint64_t first_yz = axis_cell(-0.5 * extent_m, 1.0 / cell_m);
  // The first cell of the extent's cube goes to bucket 0 (unsigned arithmetic wraps as the mask does).
  return {row * row, row, 0 - (first * row * row + first_yz * row + first_yz)};
}

template <bool kInOrder>
void BroadPhaseGrid::key_boxes(double inverse_column_m, double inverse_cell_m, const CellOrder& cells,
                               std::size_t begin, std::size_t end) {
  // Local restrict copies of every pointer and value, so the loop vectorises (see grow_boxes).
  const float* __restrict lo_x = box_lo_[0].data();
  const float* __restrict lo_y = box_lo_[1].data();
  const float* __restrict lo_z = box_lo_[2].data();
  const float* __restrict hi_x = box_hi_[0].data();
  const float* __restrict hi_y = box_hi_[1].data();
  const float* __restrict hi_z = box_hi_[2].data();
  std::uint64_t* __restrict keys = box_key_.data();
  std::uint32_t* __restrict buckets = box_bucket_.data();
  std::uint8_t* __restrict crosses = box_crosses_.data();
  const CellOrder order = cells;  // a local copy: the loop must not re-read it after each store
#pragma omp simd
  for (std::size_t i = begin; i < end; ++i) {
    const std::uint64_t cx = axis_cell(lo_x[i], inverse_column_m), cy = axis_cell(lo_y[i], inverse_cell_m),
                        cz = axis_cell(lo_z[i], inverse_cell_m);
    const std::uint64_t key = (cx << (2 * kAxisBits)) | (cy << kAxisBits) | cz;
    keys[i] = key;
    // Monotone cells: a box whose upper corner is in its lower corner's cell along an axis lies below
    // every lower corner of a later cell on that axis.
    const std::uint32_t bits = (axis_cell(hi_x[i], inverse_column_m) != cx ? kCrossesX : 0u) |
                               (axis_cell(hi_y[i], inverse_cell_m) != cy ? 2u : 0u) |
                               (axis_cell(hi_z[i], inverse_cell_m) != cz ? 4u : 0u);
    crosses[i] = static_cast<std::uint8_t>(bits);
    buckets[i] = static_cast<std::uint32_t>(bucket_in_region<kInOrder>(key, order));
  }
}

template <std::size_t kBorders>
void BroadPhaseGrid::add_regions(const RegionMap& regions, std::size_t begin, std::size_t end) {
  const std::uint64_t* __restrict keys = box_key_.data();
  const std::uint8_t* __restrict crosses = box_crosses_.data();
  std::uint32_t* __restrict buckets = box_bucket_.data();
  const RegionMap map = regions;  // a local copy: the loop must not re-read it after each store
#pragma omp simd
  for (std::size_t i = begin; i < end; ++i) {
    const auto column = static_cast<std::uint32_t>(column_of(keys[i]));  // below 2^kAxisBits
    const std::uint32_t region = map.region_of<kBorders>(column), next = map.region_of<kBorders>(column + 1);
    const bool ghosted = (crosses[i] & kCrossesX) != 0 && next != region;
    buckets[i] |= (region << map.region_bits) | (ghosted ? (next + 1) << kGhostRegionShift : 0u);
  }
}

std::pair<std::size_t, std::size_t> BroadPhaseGrid::sorted_slots(std::size_t t, std::size_t threads) const {
  const auto [first, last] = partition_run(t, threads);
  return {first < partitions_ ? partition_start_[first] : slots_in_grid_,
          last < partitions_ ? partition_start_[last] : slots_in_grid_};
}

void BroadPhaseGrid::record_region_costs(const double* seconds, std::size_t team) {
  if (team != regions_ || regions_ < 2) return;  // each thread's run a region: else not one region's
  for (std::size_t r = 0; r < regions_; ++r) {
    const auto [first, last] = sorted_slots(r, team);
    if (last <= first || !(seconds[r] > 0.0)) return;
  }
  smooth_costs(cost_per_slot_s_, regions_, [&](std::size_t r) {
    const auto [first, last] = sorted_slots(r, team);
    return seconds[r] / static_cast<double>(last - first);
  });
}

ThreadChunk BroadPhaseGrid::pass_chunk(const ChunkLayout* layout, std::size_t n, std::size_t t,
                                       std::size_t team) const {
  if (team < 2 || team != costed_chunk_team_) return thread_chunk(layout, n, t, team);
  // Chunk u's objects weighted by 1 / its thread's cost per object: chunk k starts where the weighted
  // objects below it make k / team of the whole. Every thread computes the same starts.
  double below_t = 0.0, below_next = 0.0, total = 0.0;
  for (std::size_t u = 0; u < team; ++u) {
    const ThreadChunk c = thread_chunk(layout, n, u, team);
    const double weighted = static_cast<double>(c.end - c.begin) / chunk_cost_per_object_s_[u];
    if (u < t) below_t += weighted;
    if (u <= t) below_next += weighted;
    total += weighted;
  }
  auto start = [&](double weighted_below) {
    const auto i = static_cast<std::size_t>(static_cast<double>(n) * (weighted_below / total));
    return std::min(n, i) / kChunkAlign * kChunkAlign;
  };
  return {t == 0 ? 0 : start(below_t), t + 1 == team ? n : start(below_next)};
}

void BroadPhaseGrid::record_pass_costs(const double* seconds, const std::size_t* objects, std::size_t team) {
  // Reported as if this grid's last build had measured them.
  if (team > thread_pass_.size()) thread_pass_.resize(team);
  for (std::size_t u = 0; u < team; ++u) thread_pass_[u] = ThreadPass{seconds[u], objects[u]};
  record_pass_costs(team);
}

void BroadPhaseGrid::record_pass_costs(std::size_t team) {
  if (team < 2 || team > thread_pass_.size()) return;
  // A chunk emptied (or not timed): keep the last costs.
  for (std::size_t u = 0; u < team; ++u)
    if (thread_pass_[u].objects == 0 || !(thread_pass_[u].seconds > 0.0)) return;
  if (team != costed_chunk_team_) {  // costs measured with another team say nothing of this one's
    chunk_cost_per_object_s_.assign(team, 0.0);
    costed_chunk_team_ = team;
  }
  smooth_costs(chunk_cost_per_object_s_.data(), team, [&](std::size_t u) {
    return thread_pass_[u].seconds / static_cast<double>(thread_pass_[u].objects);
  });
}

bool BroadPhaseGrid::slots_sorted(std::size_t t, std::size_t threads) const {
  if (layout_ready_->count.load(std::memory_order_acquire) != threads + 1) return false;
  const auto [first, last] = partition_run(t, threads);
  if (first >= last) return true;
  const std::uint32_t per_region = 1u << (region_bits_ - fine_bits_);
  for (std::size_t r = region_of_partition(first); r <= region_of_partition(last - 1); ++r)
    if (region_progress_[r].count.load(std::memory_order_acquire) != per_region) return false;
  return true;
}

void BroadPhaseGrid::collect_oversized_pairs(std::size_t begin, std::size_t end,
                                             std::vector<CandidatePair>& out) const {
  const std::size_t n = box_key_.size();
  const float *lo_x = box_lo_[0].data(), *lo_y = box_lo_[1].data(), *lo_z = box_lo_[2].data();
  const float *hi_x = box_hi_[0].data(), *hi_y = box_hi_[1].data(), *hi_z = box_hi_[2].data();
  // The overlap tests a block at a time in vector lanes (a far-out object, common in real catalogs,
  // overlaps nothing), then the hits in order.
  constexpr std::size_t kBlock = 256;
  alignas(64) unsigned char hit[kBlock];
  for (std::size_t o = begin; o < end; ++o) {
    const std::size_t i = oversized_[o];
    const float a_lo_x = lo_x[i], a_lo_y = lo_y[i], a_lo_z = lo_z[i];
    const float a_hi_x = hi_x[i], a_hi_y = hi_y[i], a_hi_z = hi_z[i];
    // Whether object j's box overlaps object i's (bitwise ands: no branches in the vector lanes).
    auto overlaps = [&](std::size_t j) {
      return (a_lo_x <= hi_x[j]) & (lo_x[j] <= a_hi_x) & (a_lo_y <= hi_y[j]) & (lo_y[j] <= a_hi_y) &
             (a_lo_z <= hi_z[j]) & (lo_z[j] <= a_hi_z);
    };
    if (!(a_lo_x <= kFarOut_m && -kFarOut_m <= a_hi_x && a_lo_y <= kFarOut_m && -kFarOut_m <= a_hi_y &&
          a_lo_z <= kFarOut_m && -kFarOut_m <= a_hi_z)) {
      // Its box misses the cube that holds every grid box (far out): only the later oversized objects
      // can meet it, in the order the scan below would find them.
      for (std::size_t p = o + 1; p < oversized_.size(); ++p) {
        const std::size_t j = oversized_[p];
        if (overlaps(j))
          out.push_back(CandidatePair{static_cast<std::uint32_t>(i), static_cast<std::uint32_t>(j)});
      }
      continue;
    }
    for (std::size_t j0 = 0; j0 < n; j0 += kBlock) {
      const std::size_t m = std::min(kBlock, n - j0);
      std::fill(hit + m, hit + kBlock, 0);
#pragma omp simd
      for (std::size_t d = 0; d < m; ++d) hit[d] = overlaps(j0 + d);
      for (std::size_t w = 0; w < m; w += 8) {
        std::uint64_t word;
        std::memcpy(&word, hit + w, sizeof word);
        for (; word != 0; word &= word - 1) {
          const std::size_t j = j0 + w + static_cast<std::size_t>(std::countr_zero(word)) / 8;
          // Oversized with oversized: once, from the lower index.
          if (j == i || (oversized_flag_[j] && j < i)) continue;
          out.push_back(CandidatePair{static_cast<std::uint32_t>(i), static_cast<std::uint32_t>(j)});
        }
      }
    }
  }
}

#ifdef __AVX512F__
// GCC 12's intrinsics start some results from _mm512_undefined_*(), which -Wmaybe-uninitialized
// mistakes for a read of an uninitialised value once inlined.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
void BroadPhaseGrid::filter_hits(HitBatch& hits, std::vector<CandidatePair>& out) const {
  const float *lo0 = slot_box_[0].data(), *lo1 = slot_box_[1].data(), *lo2 = slot_box_[2].data();
  const float *hi0 = slot_box_[3].data(), *hi1 = slot_box_[4].data(), *hi2 = slot_box_[5].data();
  const std::uint32_t* chord = slot_chord_.data();
  const std::uint64_t* key = slot_key_.data();
  const std::size_t count = hits.count;
  // Each hit is kept when slot m is in the cell asked for (buckets hold other cells too: without this
  // check a pair could be found from both sides) and the chord filter (step_chord.hpp) keeps the pair.
  // A slot's line for the filter is the corners of its box chosen by its direction bits: rising ? lo
  // : hi without a branch (the bits are random), exact since lo - hi of two floats is exact in double.
#ifdef __AVX512F__
  // Eight hits at once, the same operations in the same order as the portable code below (so the
  // same outcome bit for bit), on slots gathered from the arrays.
  for (std::size_t h = 0; h < count; h += 8) {
    const __mmask8 valid = count - h >= 8 ? __mmask8{0xFF} : static_cast<__mmask8>((1u << (count - h)) - 1u);
    const __m256i self = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(hits.self + h));
    const __m256i other = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(hits.other + h));
    const __m512d zero = _mm512_setzero_pd();
    auto gather = [&](const float* array, __m256i slots) {
      return _mm512_cvtps_pd(_mm256_mmask_i32gather_ps(_mm256_setzero_ps(), valid, slots, array, 4));
    };
    // A slot's line and its reach, from its box and its chord word.
    auto line = [&](__m256i slots, __m512d start[3], __m512d end[3], __m512d& reach) {
      const __m256i word = _mm256_mmask_i32gather_epi32(_mm256_setzero_si256(), valid, slots, chord, 4);
      reach = _mm512_cvtps_pd(_mm256_castsi256_ps(word));
      const float* const lo[3] = {lo0, lo1, lo2};
      const float* const hi[3] = {hi0, hi1, hi2};
      for (int axis = 0; axis < 3; ++axis) {
        const __m512d l = gather(lo[axis], slots), u = gather(hi[axis], slots);
        const __m512d rising =
            _mm512_cvtepi32_pd(_mm256_and_si256(_mm256_srli_epi32(word, axis), _mm256_set1_epi32(1)));
        start[axis] = _mm512_add_pd(u, _mm512_mul_pd(rising, _mm512_sub_pd(l, u)));
        end[axis] = _mm512_add_pd(l, _mm512_mul_pd(rising, _mm512_sub_pd(u, l)));
      }
    };
    __m512d a0[3], a1[3], b0[3], b1[3], reach_a, reach_b;
    line(self, a0, a1, reach_a);
    line(other, b0, b1, reach_b);
    // chords_may_come_within, lane by lane.
    __m512d c0[3], u[3], uu = zero, c0u = zero, c0c0 = zero;
    for (int axis = 0; axis < 3; ++axis) {
      c0[axis] = _mm512_sub_pd(a0[axis], b0[axis]);
      u[axis] = _mm512_sub_pd(_mm512_sub_pd(a1[axis], b1[axis]), c0[axis]);
      uu = _mm512_add_pd(uu, _mm512_mul_pd(u[axis], u[axis]));
      c0u = _mm512_add_pd(c0u, _mm512_mul_pd(c0[axis], u[axis]));
      c0c0 = _mm512_add_pd(c0c0, _mm512_mul_pd(c0[axis], c0[axis]));
    }
    const __m512d t = _mm512_min_pd(_mm512_max_pd(_mm512_sub_pd(zero, c0u), zero), uu);
    const __m512d reach_sum = _mm512_add_pd(_mm512_add_pd(reach_a, reach_b), _mm512_set1_pd(kChordMargin_m));
    const __m512d left =
        _mm512_add_pd(_mm512_mul_pd(uu, c0c0), _mm512_mul_pd(t, _mm512_add_pd(_mm512_add_pd(c0u, c0u), t)));
    const __m512d right = _mm512_mul_pd(
        _mm512_add_pd(
            _mm512_mul_pd(_mm512_mul_pd(reach_sum, reach_sum), _mm512_set1_pd(1.0 + kChordRelativeSlack)),
            _mm512_mul_pd(_mm512_set1_pd(kChordCancellationSlack), c0c0)),
        uu);
    // The cell-key check only for the pairs the filter keeps (about 1 in 1,000 at 320k objects): the
    // keys are the one array of the other slot that the walk has not just read, so checking every hit
    // would cost a cache miss each.
    unsigned keep = _mm512_mask_cmp_pd_mask(valid, left, right, _CMP_LE_OQ);
    while (keep != 0) {
      const std::size_t hit = h + static_cast<std::size_t>(std::countr_zero(keep));
      keep &= keep - 1;
      if (key[hits.other[hit]] - hits.key_lo[hit] <= hits.span[hit])
        out.push_back(CandidatePair{slot_index_[hits.self[hit]], slot_index_[hits.other[hit]]});
    }
  }
#else
  auto line = [&](std::uint32_t k, double start[3], double end[3]) {
    const std::uint32_t ends = chord[k];
    const float* const lo[3] = {lo0, lo1, lo2};
    const float* const hi[3] = {hi0, hi1, hi2};
    for (int axis = 0; axis < 3; ++axis) {
      const double l = lo[axis][k], u = hi[axis][k];
      const double rising = static_cast<double>((ends >> axis) & 1u);
      start[axis] = u + rising * (l - u);
      end[axis] = l + rising * (u - l);
    }
  };
  for (std::size_t h = 0; h < count; ++h) {
    const std::uint32_t k = hits.self[h], m = hits.other[h];
    double a0[3], a1[3], b0[3], b1[3];
    line(k, a0, a1);
    line(m, b0, b1);
    if (chords_may_come_within(a0, a1, chord_word_reach_m(chord[k]), b0, b1, chord_word_reach_m(chord[m])) &&
        key[m] - hits.key_lo[h] <= hits.span[h])
      out.push_back(CandidatePair{slot_index_[k], slot_index_[m]});
  }
#endif
  hits.count = 0;
}

void BroadPhaseGrid::pair_with_slots(std::size_t k, std::size_t first, std::size_t last, std::uint64_t key_lo,
                                     std::uint64_t span, HitBatch& hits,
                                     std::vector<CandidatePair>& out) const {
  if (last <= first) return;
  const float *lo0 = slot_box_[0].data(), *lo1 = slot_box_[1].data(), *lo2 = slot_box_[2].data();
  const float *hi0 = slot_box_[3].data(), *hi1 = slot_box_[4].data(), *hi2 = slot_box_[5].data();
  const float a_lo0 = lo0[k], a_lo1 = lo1[k], a_lo2 = lo2[k], a_hi0 = hi0[k], a_hi1 = hi1[k], a_hi2 = hi2[k];
#ifdef __AVX512F__
  // 16 box tests at once into a mask register (ordered compares: false with NaN, as the portable test
  // below); slots past `last` are read (the arrays are padded) and masked off (they may be another
  // region's, which its sort may be writing meanwhile: no result depends on their lanes). Even a range of one
  // or two slots is cheaper this way than one slot at a time (20k objects: 134 -> 127 ns per object-step).
  static_assert(kLanes == 16);
  const __m512 lo0_a = _mm512_set1_ps(a_lo0), lo1_a = _mm512_set1_ps(a_lo1), lo2_a = _mm512_set1_ps(a_lo2);
  const __m512 hi0_a = _mm512_set1_ps(a_hi0), hi1_a = _mm512_set1_ps(a_hi1), hi2_a = _mm512_set1_ps(a_hi2);
  const __m512i self = _mm512_set1_epi32(static_cast<int>(k));
  const __m512i span_lanes = _mm512_set1_epi32(static_cast<int>(span));
  const __m512i key_lo_lanes = _mm512_set1_epi64(static_cast<long long>(key_lo));
  const __m512i lane = _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
  // The chord filter's cheap float version on the group's lanes, against slot k's line (see
  // chords_may_come_within_float): nearly every box hit fails it (at 320,000 objects, 2.5 box hits per
  // object and step, of which 1 in 1,000 is kept), so only its survivors go to the batch, where the
  // double filter decides.
  const std::uint32_t* chord = slot_chord_.data();
  const std::uint32_t word_a = chord[k];
  // Slot k's line, without a branch (its direction bits are random): where the filter runs on every
  // group, once; elsewhere only for the groups that hit, which are few.
  // (Both lambdas are forced inline: outlined, as GCC did once the walk's caller grew, they read the
  // broadcast registers through memory and the walk ran 16 % slower.)
  __m512 start_a[3], end_a[3];
  auto self_line = [&]() __attribute__((always_inline)) {
    const __m512 lo_a[3] = {lo0_a, lo1_a, lo2_a}, hi_a[3] = {hi0_a, hi1_a, hi2_a};
    for (int axis = 0; axis < 3; ++axis) {
      const auto rising = static_cast<__mmask16>(0u - ((word_a >> axis) & 1u));
      start_a[axis] = _mm512_mask_blend_ps(rising, hi_a[axis], lo_a[axis]);
      end_a[axis] = _mm512_mask_blend_ps(rising, lo_a[axis], hi_a[axis]);
    }
  };
  // Overlapping boxes' corners are within 2 cell edges on each axis, so the pairs' relative lines within
  // 3.5. Past kFloatFilterMaxCell_m the float filter's products could overflow: every box hit then goes
  // to the double filter.
  const double widest_edge_m = std::max(cell_size_m_, column_width_m_);
  const float filter_extent_m = static_cast<float>(3.5 * widest_edge_m);
  const __mmask16 filter_off = widest_edge_m <= kFloatFilterMaxCell_m ? 0 : 0xFFFF;
  const float* const lo_arrays[3] = {lo0, lo1, lo2};
  const float* const hi_arrays[3] = {hi0, hi1, hi2};
  // Dense regions hit boxes in most groups of lanes, at random: there the float filter runs on every
  // group without a branch (a branch on the box hits would be mispredicted half the time). Sparse
  // regions, and the long ranges of dense debris clouds, hit in almost none: there it runs only on
  // groups that hit (a branch predicted right). Which regime holds is read from the hit rate so far;
  // either way the batch gets the same hits.
  std::size_t groups = 0, found = 0;
  auto walk = [&](auto filter_every_group) __attribute__((always_inline)) {
    if constexpr (decltype(filter_every_group)::value) self_line();
    for (std::size_t base = first; base < last; base += kLanes, ++groups) {
      __m512 lo[3], hi[3];
      for (int axis = 0; axis < 3; ++axis) {
        lo[axis] = _mm512_loadu_ps(lo_arrays[axis] + base);
        hi[axis] = _mm512_loadu_ps(hi_arrays[axis] + base);
      }
      __mmask16 hit = _mm512_cmp_ps_mask(lo0_a, hi[0], _CMP_LE_OQ);
      hit = _mm512_mask_cmp_ps_mask(hit, lo[0], hi0_a, _CMP_LE_OQ);
      hit = _mm512_mask_cmp_ps_mask(hit, lo1_a, hi[1], _CMP_LE_OQ);
      hit = _mm512_mask_cmp_ps_mask(hit, lo[1], hi1_a, _CMP_LE_OQ);
      hit = _mm512_mask_cmp_ps_mask(hit, lo2_a, hi[2], _CMP_LE_OQ);
      hit = _mm512_mask_cmp_ps_mask(hit, lo[2], hi2_a, _CMP_LE_OQ);
      if (last - base < kLanes) hit &= static_cast<__mmask16>((1u << (last - base)) - 1u);
      if constexpr (!decltype(filter_every_group)::value) {
        if (hit == 0) continue;
        self_line();
      }
      found += static_cast<std::size_t>(std::popcount(static_cast<unsigned>(hit)));
      const __m512i word = _mm512_loadu_si512(chord + base);
      __m512 start_b[3], end_b[3];
      for (int axis = 0; axis < 3; ++axis) {
        const __mmask16 rising = _mm512_test_epi32_mask(word, _mm512_set1_epi32(1 << axis));
        start_b[axis] = _mm512_mask_blend_ps(rising, hi[axis], lo[axis]);
        end_b[axis] = _mm512_mask_blend_ps(rising, lo[axis], hi[axis]);
      }
      const __mmask16 keep =
          hit & (chords_may_come_within_float(start_a, end_a, _mm512_set1_ps(chord_word_reach_m(word_a)),
                                              start_b, end_b, _mm512_castsi512_ps(word), filter_extent_m) |
                 filter_off);
      if (keep == 0) continue;  // nearly always: a branch predicted right
      // The survivors' slots, packed, go to the batch's end, and the range's own values into all 16
      // entries there, of which the first popcount(keep) count. (The compress is done in a register:
      // its store form is slow on some cores.)
      const std::size_t at = hits.count;
      const __m512i slots = _mm512_add_epi32(_mm512_set1_epi32(static_cast<int>(base)), lane);
      _mm512_storeu_si512(hits.other + at, _mm512_maskz_compress_epi32(keep, slots));
      _mm512_storeu_si512(hits.self + at, self);
      _mm512_storeu_si512(hits.span + at, span_lanes);
      _mm512_storeu_si512(hits.key_lo + at, key_lo_lanes);
      _mm512_storeu_si512(hits.key_lo + at + 8, key_lo_lanes);
      hits.count = at + static_cast<std::size_t>(std::popcount(static_cast<unsigned>(keep)));
      if (hits.nearly_full()) filter_hits(hits, out);
    }
  };
  if (hits.dense())
    walk(std::true_type{});
  else
    walk(std::false_type{});
  hits.record(groups, found);
#else
  auto add_hit = [&](std::size_t m) {
    hits.self[hits.count] = static_cast<std::uint32_t>(k);
    hits.other[hits.count] = static_cast<std::uint32_t>(m);
    hits.span[hits.count] = static_cast<std::uint32_t>(span);
    hits.key_lo[hits.count] = key_lo;
    if (++hits.count == HitBatch::kCapacity) filter_hits(hits, out);
  };
  // Short ranges (sparse populations) one slot at a time: the lanes' fixed cost would dominate.
  if (last - first < kLanes / 2) {
    for (std::size_t m = first; m < last; ++m) {
      const bool overlap = (a_lo0 <= hi0[m]) & (lo0[m] <= a_hi0) & (a_lo1 <= hi1[m]) & (lo1[m] <= a_hi1) &
                           (a_lo2 <= hi2[m]) & (lo2[m] <= a_hi2);
      if (overlap) add_hit(m);
    }
    return;
  }
  for (std::size_t base = first; base < last; base += kLanes) {
    // kLanes box tests at once, without branches (slots past `last` are read, then masked off).
    unsigned char hit[kLanes];
#pragma omp simd
    for (std::size_t l = 0; l < kLanes; ++l) {
      const std::size_t m = base + l;
      hit[l] = static_cast<unsigned char>((a_lo0 <= hi0[m]) & (lo0[m] <= a_hi0) & (a_lo1 <= hi1[m]) &
                                          (lo1[m] <= a_hi1) & (a_lo2 <= hi2[m]) & (lo2[m] <= a_hi2));
    }
    std::uint64_t word[kLanes / 8];
    std::memcpy(word, hit, sizeof hit);
    for (std::size_t w = 0; w < kLanes / 8; ++w) {
      for (std::uint64_t bits = word[w]; bits != 0; bits &= bits - 1) {
        const std::size_t m = base + 8 * w + static_cast<std::size_t>(std::countr_zero(bits)) / 8;
        if (m >= last) break;
        add_hit(m);
      }
    }
  }
#endif
}
#ifdef __AVX512F__
#pragma GCC diagnostic pop
#endif

void BroadPhaseGrid::pair_with_buckets(std::size_t k, std::size_t region, std::size_t first,
                                       std::size_t count, std::size_t from, std::uint64_t key_lo,
                                       std::uint64_t span, HitBatch& hits,
                                       std::vector<CandidatePair>& out) const {
  if (first + count <= region_mask_ + 1) {
    // One contiguous range (`from` lies in the first bucket or before it).
    pair_with_slots(k, std::max<std::size_t>(bucket_start_[region + first], from),
                    bucket_start_[region + first + count], key_lo, span, hits, out);
  } else {
    for (std::size_t d = 0; d < count; ++d) {  // wraps around the end of the region
      const std::size_t b = region | ((first + d) & region_mask_);
      pair_with_slots(k, d == 0 ? std::max<std::size_t>(bucket_start_[b], from) : bucket_start_[b],
                      bucket_start_[b + 1], key_lo, span, hits, out);
    }
  }
}

void BroadPhaseGrid::collect_pairs(std::size_t slot_begin, std::size_t slot_end,
                                   std::vector<CandidatePair>& out) const {
  HitBatch hits;
  const bool in_order = cells_in_order();
  auto collect_in = [&](std::size_t first, std::size_t last, std::size_t region) {
    in_order ? collect_pairs_in<true>(first, last, region, hits, out)
             : collect_pairs_in<false>(first, last, region, hits, out);
  };
  if (regions_ == 1) {
    collect_in(slot_begin, slot_end, 0);
  } else {
    // Region by region (each holds a contiguous run of slots, its ghosts among them), so the region of
    // every row a slot looks up is known.
    for (std::size_t r = 0; r < regions_; ++r) {
      const std::size_t region = r << region_bits_;
      const std::size_t first = std::max<std::size_t>(slot_begin, bucket_start_[region]);
      const std::size_t last = std::min<std::size_t>(slot_end, bucket_start_[region + region_mask_ + 1]);
      if (first < last) collect_in(first, last, region);
    }
  }
  filter_hits(hits, out);
}

template <bool kInOrder>
void BroadPhaseGrid::collect_pairs_in(std::size_t slot_begin, std::size_t slot_end, std::size_t region,
                                      HitBatch& hits, std::vector<CandidatePair>& out) const {
  // In order, the forward rows' buckets are at fixed offsets from the cell's own.
  const CellOrder order = cell_order_;
  const std::uint64_t row_offsets[4] = {order.row_stride, order.plane_stride - order.row_stride,
                                        order.plane_stride, order.plane_stride + order.row_stride};
  for (std::size_t k = slot_begin; k < slot_end; ++k) {
    const std::uint64_t key = slot_key_[k];
    const std::uint32_t crosses = slot_crosses_[k];
    // z cells of a neighbour row: z - 1 and z, and z + 1 only if the box reaches into the next z cell.
    const std::size_t z_cells = (crosses & 4u) ? 3 : 2;
    // A ghost walks only the next column's rows (1-3): its own column's are its box's, in the last
    // region. `walks` has kGhost set for the slots that walk their own column.
    const std::uint32_t walks = crosses ^ kGhost;
    // Own row: the same cell (slots after k) and the next z cell, in buckets b and b + 1.
    const std::size_t own = bucket_in_region<kInOrder>(key, order);
    if (walks & kGhost) pair_with_buckets(k, region, own, z_cells - 1, k + 1, key, 1, hits, out);
    // The forward rows, z cells -1..+1: buckets b' - 1 .. b' + 1. Rows at y + 1 only if the box
    // reaches into the next y cell, rows at x + 1 only if it reaches into the next x cell (in this
    // region: a box whose next column is another region's has dropped kCrossesX, and its ghost there
    // walks those rows).
    for (int r = 0; r < 4; ++r) {
      const std::uint32_t needs = kForwardRowNeeds[r] | (r == 0 ? kGhost : 0u);
      if ((walks & needs) != needs) continue;
      const std::uint64_t centre = key + kForwardRows[r];
      const std::size_t first =
          ((kInOrder ? own + row_offsets[r] : bucket_in_region<false>(centre, order)) - 1) & region_mask_;
      // Many neighbour rows are empty: the occupancy bitmap answers.
      if (!any_occupied(region, first, z_cells)) continue;
      pair_with_buckets(k, region, first, z_cells, 0, centre - 1, z_cells - 1, hits, out);
    }
  }
}

}  // namespace kessler
