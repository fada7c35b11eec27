// Burn-up: objects whose altitude falls below a minimum (default 150 km) leave the simulation.
#pragma once

#include <vector>

#include "core/population/population.hpp"

namespace kessler {

struct BurnUp {
  ObjectId id = 0;
  double time_s = 0.0;      // seconds since the scenario epoch (end of the step it was found in)
  double altitude_m = 0.0;  // altitude above the equatorial radius at that time
};

// The squared distance from the Earth's centre [m^2] below which an object burns up: (R + h)^2 for the
// equatorial radius R and min_altitude_m h (0 where R + h <= 0).
double burn_up_radius2(double min_altitude_m);

// The burn-up test on one position [m]: within sqrt(radius2) of the Earth's centre, or not finite (a
// NaN state leaves too). Squared radii: no square root per object; r^2 >= (R + h)^2 is r >= R + h.
inline bool burns_up(double x, double y, double z, double radius2) {
  return !(x * x + y * y + z * z >= radius2);
}

// Flags (1) the positions of `states` that burn up (burns_up), in parallel; flags is resized to them.
void flag_burn_ups(const StateArrays& states, double radius2, std::vector<char>& flags);

// The flagged objects' events, in population order (flags from flag_burn_ups, or from a propagator that
// applied burns_up in its own pass: StepRequest).
std::vector<BurnUp> flagged_burn_ups(const Population& population, double time_s,
                                     const std::vector<char>& flags);

// Both: the objects of `population` below min_altitude_m, in population order, and their removal flags
// (flags.size() == population.size(); pass them to Population::remove_flagged).
std::vector<BurnUp> find_burn_ups(const Population& population, double min_altitude_m, double time_s,
                                  std::vector<char>& flags);

}  // namespace kessler
