// The broad-phase grid's boxes: each object's motion over the step in a box grown by its threshold share
// and rounded outwards to floats (grid_boxes.cpp), with what the passes after it read of each object.
#pragma once

#include <cstdint>

namespace kessler::grid {

// Each object's flags from the box pass: bits 0-2 the chord's direction per axis (step_chord.hpp), and
// whether it is oversized (kept out of the grid and tested against every object).
inline constexpr std::uint32_t kChordEndsMask = 7u;
inline constexpr std::uint32_t kOversizedFlag = 8u;

// Boxes reaching beyond this along any axis [m] (2.6 times the Moon's distance) are far out, and
// oversized: rounding widens a box there by up to 240 m a side, so real catalogs' entries at ~10^12 m
// would otherwise stay in the grid with boxes hundreds of km wide and set every cell's edge. Each grid
// box lies inside the cube of this half-edge, so an oversized box that misses the cube can meet only
// other oversized boxes.
inline constexpr float kFarOut_m = 1.0e9f;

}  // namespace kessler::grid
