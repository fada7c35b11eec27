// The grid's cells: the key pass (cell keys, buckets, crossing bits and regions of each box in the
// thread's chunk), the cells' order in the buckets, and the cell edges and extent the next build starts
// from (coarser cells where the population is sparse).
//
// GCC 12 vectorises the key pass (a floor and clamps per axis) only where floating-point operations may
// be assumed not to trap. No value changes (only exception flags could, and the core reads none); the
// same pragma as in symplectic_propagator.cpp.
#pragma GCC optimize("no-trapping-math")

#include "core/conjunctions/grid_cells.hpp"

#include <algorithm>
#include <cmath>

#include "core/conjunctions/broad_phase_grid.hpp"

namespace kessler {
namespace {

using grid::axis_cell;
using grid::CellOrder;
using grid::RegionMap;

// A guessed cell more than this factor above what the step asks for is shrunk.
constexpr double kCellShrinkRatio = 1.05;
// Coarser cells where the population is sparse: the cell grows by kCoarseningStep a build while the
// last build held fewer than kSparseObjectsPerCell objects per occupied cell, and shrinks back (never
// below the largest box) above kDenseObjectsPerCell. The walk's cost per object is a few neighbour-row
// lookups plus 16-lane box tests over the rows' slots, so a cell holding one or two objects pays the
// lookups for almost no tests; much fuller cells pay for tests of boxes too far apart to meet.
constexpr double kSparseObjectsPerCell = 4.0, kDenseObjectsPerCell = 8.0;
constexpr double kCoarseningStep = 1.25, kMaxCoarsening = 16.0;
// With several regions, each keeps at least this many cell columns (the borders fall on column edges:
// fewer columns would balance the threads badly).
constexpr double kMinColumnsPerRegion = 4.0;

// The coarsening for the next build, after a build whose sort put `slots` objects in `occupied` cells.
double next_coarsening(double coarsening, std::size_t slots, std::size_t occupied) {
  if (occupied == 0) return coarsening;
  const double per_cell = static_cast<double>(slots) / static_cast<double>(occupied);
  if (per_cell < kSparseObjectsPerCell) return std::min(coarsening * kCoarseningStep, kMaxCoarsening);
  if (per_cell > kDenseObjectsPerCell) return std::max(coarsening / kCoarseningStep, 1.0);
  return coarsening;
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

}  // namespace

void BroadPhaseGrid::key_chunk(ThreadBuild& b, double column_m, double cell_m) {
  const double inverse_column = 1.0 / column_m;
  // Each region starts at the column edge nearest its border.
  for (std::size_t s = 0; s + 1 < regions_; ++s)
    b.map.first_column[s] =
        static_cast<std::uint32_t>(axis_cell(b.borders_m[s] + 0.5 * column_m, inverse_column));
  b.map.order = cell_order(b.extent_m, column_m, cell_m, b.map);
  if (b.map.order.in_order())
    key_boxes<true>(inverse_column, 1.0 / cell_m, b.map.order, b.begin, b.end);
  else
    key_boxes<false>(inverse_column, 1.0 / cell_m, b.map.order, b.begin, b.end);
  // The borders the region pass compares with: one with two regions (2 threads), else all.
  if (regions_ == 2)
    add_regions<1>(b.map, b.begin, b.end);
  else if (regions_ > 2)
    add_regions<kMaxRegions - 1>(b.map, b.begin, b.end);
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
  const std::size_t region_mask = region_mask_;
#pragma omp simd
  for (std::size_t i = begin; i < end; ++i) {
    const std::uint64_t cx = axis_cell(lo_x[i], inverse_column_m), cy = axis_cell(lo_y[i], inverse_cell_m),
                        cz = axis_cell(lo_z[i], inverse_cell_m);
    const std::uint64_t key = (cx << (2 * grid::kAxisBits)) | (cy << grid::kAxisBits) | cz;
    keys[i] = key;
    // Monotone cells: a box whose upper corner is in its lower corner's cell along an axis lies below
    // every lower corner of a later cell on that axis.
    const std::uint32_t bits = (axis_cell(hi_x[i], inverse_column_m) != cx ? grid::kCrossesX : 0u) |
                               (axis_cell(hi_y[i], inverse_cell_m) != cy ? 2u : 0u) |
                               (axis_cell(hi_z[i], inverse_cell_m) != cz ? 4u : 0u);
    crosses[i] = static_cast<std::uint8_t>(bits);
    buckets[i] = static_cast<std::uint32_t>(grid::bucket_in_region<kInOrder>(key, order, region_mask));
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
    const auto column = static_cast<std::uint32_t>(grid::column_of(keys[i]));  // below 2^kAxisBits
    const std::uint32_t region = map.region_of<kBorders>(column), next = map.region_of<kBorders>(column + 1);
    const bool ghosted = (crosses[i] & grid::kCrossesX) != 0 && next != region;
    buckets[i] |= (region << map.region_bits) | (ghosted ? (next + 1) << grid::kGhostRegionShift : 0u);
  }
}

CellOrder BroadPhaseGrid::cell_order(double extent_m, double column_m, double cell_m,
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

void BroadPhaseGrid::update_coarsening(std::size_t threads) {
  // The coarsening follows the last build's objects per occupied cell.
  // A shared grid sorted its part's cells only: it follows all parts' (set_all_parts_occupied), or keeps
  // its coarsening, so that every part guesses the same cells.
  const std::size_t occupied = share_parts_ == 1           ? sorted_occupied_cells()
                               : all_parts_occupied_known_ ? all_parts_occupied_
                                                           : 0;
  all_parts_occupied_known_ = false;
  occupancy_team_ = threads;
  coarsening_ = next_coarsening(coarsening_, slots_in_grid_, occupied);
}

std::size_t BroadPhaseGrid::sorted_occupied_cells() const {
  if (region_share().sub != 0) return 0;  // another part counts this region's cells
  std::size_t occupied = 0;
  for (std::size_t u = 0; u < occupancy_team_; ++u) occupied += thread_occupied_[u];
  return occupied;
}

void BroadPhaseGrid::sample_extent(const ThreadBuild& b) {
  // How far the population spreads (for the next build's cell order): |lower corner| of every
  // kExtentStride-th object, binned by powers of 2^(1/4) from kExtentFirst_m.
  std::uint32_t local_hist[kExtentBins] = {};
  for (std::size_t i = b.begin; i < b.end; i += kExtentStride) {
    if (oversized_flag_[i]) continue;
    const float r =
        std::max(std::fabs(box_lo_[0][i]), std::max(std::fabs(box_lo_[1][i]), std::fabs(box_lo_[2][i])));
    ++local_hist[extent_bin(r)];
  }
  std::copy(local_hist, local_hist + kExtentBins, &thread_extent_hist_[b.t * kExtentBins]);
}

void BroadPhaseGrid::update_extent(std::size_t threads) {
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

void BroadPhaseGrid::guess_next_cell(double cell_m, double column_m, double largest_edge_m, bool fits,
                                     double bin_width_m) {
  // The largest box edge times the coarsening (this step's cell while that fits and is not much larger;
  // the coarsening was set before the barrier).
  const double needed = grid::fitting_cell_m(largest_edge_m);
  const double wanted = needed * coarsening_;
  // With several regions the columns stay narrow enough for each region to keep a few (the borders
  // fall on column edges), and only y and z coarsen past that: the cells' volume, and so the objects
  // per cell the walk wants, no longer shrinks as the team grows.
  double wanted_column = wanted;
  if (regions_ > 1) {
    // The central 99 % of the lower x corners, from this build's bins.
    const double span_m = grid::RegionBalance::central_span_m(bin_width_m);
    wanted_column =
        std::min(wanted, std::max(needed, span_m / (kMinColumnsPerRegion * static_cast<double>(regions_))));
  }
  auto keep_or = [&](double now, double target) {
    return (fits && now >= target && now <= target * kCellShrinkRatio) ? now : target;
  };
  next_cell_m_ = keep_or(cell_m, wanted);
  next_column_m_ = keep_or(column_m, wanted_column);
}

}  // namespace kessler
