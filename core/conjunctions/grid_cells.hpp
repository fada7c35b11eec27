// The broad-phase grid's cells: how a box's lower corner becomes a cell key, how a region's cells are
// laid out in its buckets (hashed rows, or spatial order where they fit), which region of space a cell
// column lies in, and the bits a box carries for the walk. Shared by the key pass (grid_cells.cpp), the
// sort (grid_sort.cpp) and the walk (grid_walk.cpp).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>

namespace kessler::grid {

// Regions of space at most (one per thread): the x axis cut into slabs of whole cell columns.
inline constexpr std::size_t kMaxRegions = 16;

// A cell key packs the cell's indices along x, y and z, kAxisBits each with x highest, so the cells of a
// row (x, y) along z are consecutive keys.
inline constexpr int kAxisBits = 21;
inline constexpr std::uint64_t kZMask = (std::uint64_t{1} << kAxisBits) - 1;
inline constexpr std::int64_t kAxisOffset = std::int64_t{1} << (kAxisBits - 1);
inline constexpr double kAxisLimit = static_cast<double>(kAxisOffset - 2);  // keeps neighbours in range

// Cell index along one axis, clamped (clamping keeps neighbours neighbours; NaN goes to the edge).
inline std::uint64_t axis_cell(double coordinate_m, double inverse_cell_m) {
  double q = std::floor(coordinate_m * inverse_cell_m);
  if (!(q >= -kAxisLimit)) q = -kAxisLimit;
  if (!(q <= kAxisLimit)) q = kAxisLimit;
  return static_cast<std::uint64_t>(static_cast<std::int64_t>(q) + kAxisOffset);
}

inline std::uint64_t column_of(std::uint64_t cell_key) {
  return cell_key >> (2 * kAxisBits);
}

// Key offset of the row (dx, dy) (z unchanged).
constexpr std::uint64_t row_offset(int dx, int dy) {
  return static_cast<std::uint64_t>((std::int64_t{dx} << (2 * kAxisBits)) + (std::int64_t{dy} << kAxisBits));
}

// The forward half of the 26 neighbours: (0, 0, +1) in the cell's own row, and z cells -1..+1 of the
// rows (0, +1), (+1, -1), (+1, 0), (+1, +1). With the cell itself, each unordered pair of neighbouring
// cells is visited once.
inline constexpr std::uint64_t kForwardRows[4] = {row_offset(0, 1), row_offset(1, -1), row_offset(1, 0),
                                                  row_offset(1, 1)};
// The axes a box must cross into the next cell on for each forward row to hold an overlapping box
// (bit 0: x, bit 1: y).
inline constexpr std::uint32_t kForwardRowNeeds[4] = {2u, 1u, 1u, 3u};

// Crossing bits. Bits 0-2 (kCrossesX, y, z): the axes the box crosses into the next cell on. A box
// that stays in its cell along an axis cannot overlap a box whose lower corner lies in a later cell on
// that axis, so the walk skips those forward neighbours (exact: the same candidates, fewer cells
// visited). kGhost (slots only): the slot is the ghost of a box that crosses in x into another
// region's column (see kGhostRegionShift), and walks only the next-column rows.
inline constexpr std::uint32_t kCrossesX = 1, kGhost = 16;
// A box that crosses in x into another region's column gets a ghost there, and its own slot drops
// kCrossesX (its next-column rows are the ghost's). The key pass marks it in its bucket: the ghost's
// region + 1 above kGhostRegionShift (0: no ghost), so the count and the scatter read one array.
inline constexpr unsigned kGhostRegionShift = 27;
inline constexpr std::uint32_t kBucketMask = (std::uint32_t{1} << kGhostRegionShift) - 1;

// The cell edge over the largest box edge: room for the next step's boxes to grow a little, so the
// guessed cell usually fits and the keys are computed once.
inline constexpr double kCellMargin = 0.005;
// The smallest cell [m] that boxes no larger than largest_edge_m fit.
inline double fitting_cell_m(double largest_edge_m) {
  return std::max(largest_edge_m, 1.0) * (1.0 + kCellMargin);
}

// How cells are laid out in a region's buckets (bucket_in_region): row_stride 0 hashes the rows;
// otherwise cell (x, y, z) goes to x plane_stride + y row_stride + z.
struct CellOrder {
  std::uint64_t plane_stride = 0, row_stride = 0, origin = 0;
  bool in_order() const { return row_stride != 0; }
};

struct RegionMap {
  // The first cell column of regions 1, 2, ... (padded with the largest value: never reached).
  std::uint32_t first_column[kMaxRegions - 1];
  int region_bits = 0;
  CellOrder order;
  // The region of cell column `column`: the number of borders at or below it, counted over the first
  // kBorders borders (all of them by default: the unused ones are the largest column, never reached).
  // In the key pass's vector lanes these are compares with constants; a binary search, whose loads
  // depend on the last step, made four gathers of them and cost more.
  template <std::size_t kBorders = kMaxRegions - 1>
  std::uint32_t region_of(std::uint32_t column) const {
    std::uint32_t region = 0;
    for (std::size_t s = 0; s < kBorders; ++s) region += column >= first_column[s] ? 1 : 0;
    return region;
  }
};

// A cell's bucket is its region's first bucket (region << region_bits) plus bucket_in_region: its place in
// spatial order, or a hash of its row (x, y), plus its z cell, so the cells of a row along z fall in
// consecutive buckets of one region (and, sorted by bucket, in consecutive slots): the three z
// neighbours of a cell are one contiguous range (wrapping inside the region), usually on one cache
// line of the bucket table. region_mask: a region's buckets less one.
template <bool kInOrder>
std::size_t bucket_in_region(std::uint64_t cell_key, const CellOrder& order, std::size_t region_mask) {
  const std::uint64_t z = cell_key & kZMask;
  if constexpr (kInOrder) {
    const std::uint64_t y = (cell_key >> kAxisBits) & kZMask, x = cell_key >> (2 * kAxisBits);
    return static_cast<std::size_t>(x * order.plane_stride + y * order.row_stride + z + order.origin) &
           region_mask;
  } else {
    const std::uint64_t row = cell_key >> kAxisBits;
    return static_cast<std::size_t>(((row * 0x9E3779B97F4A7C15ull) >> 20) + z) & region_mask;
  }
}

}  // namespace kessler::grid
