// The mean orbital elements of one object as TLE and OMM publish them (SGP4 theory, Kozai mean motion),
// in the units SGP4 works in: radians and radians per minute.
#pragma once

#include <cstdint>
#include <string>

#include "core/time/epoch.hpp"

namespace kessler {

struct MeanElements {
  std::uint64_t catalog_number = 0;  // NORAD id (alpha-5 numbers decoded: T0000 -> 270000)
  std::string name;                  // object name where the source has one
  std::string international_designator;
  UtcEpoch epoch;                    // UTC
  double mean_motion_rad_min = 0.0;  // Kozai mean motion
  double eccentricity = 0.0;
  double inclination_rad = 0.0;
  double raan_rad = 0.0;  // right ascension of the ascending node
  double argument_of_perigee_rad = 0.0;
  double mean_anomaly_rad = 0.0;
  double bstar_per_earth_radius = 0.0;     // B* [1/ER]
  double mean_motion_dot_rad_min2 = 0.0;   // first derivative / 2 as published, converted (unused by SGP4)
  double mean_motion_ddot_rad_min3 = 0.0;  // second derivative / 6 as published, converted (unused)
};

}  // namespace kessler
