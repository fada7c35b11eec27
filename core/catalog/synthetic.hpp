// A seeded synthetic population with the distributions of the paper's dataset (the real 2022 catalog
// after the LEO filter): altitude and inclination histograms, eccentricities, RCS size classes per
// status, the active fraction. For tests and scaling studies (up to millions of objects); each object
// is a pure function of (seed, id), so the result is the same for any thread count.
#pragma once

#include <cstdint>

#include "core/catalog/object_properties.hpp"
#include "core/population/population.hpp"

namespace kessler {

struct SyntheticOptions {
  std::uint64_t objects = 0;
  double active_fraction = 0.125;  // the paper: 1,996 of 16,024
  double min_altitude_km = 300.0;  // band of the semi-major axis altitude
  double max_altitude_km = 1500.0;
  SizeSampling sizes;
  double drag_coefficient = 2.2;
  std::uint64_t first_id = 1;  // ids first_id .. first_id + objects - 1
};

// Throws std::invalid_argument for an empty or inverted band, a band outside 100..40000 km, or an
// active fraction outside 0..1.
Population generate_synthetic(const SyntheticOptions& options, std::uint64_t seed);

}  // namespace kessler
