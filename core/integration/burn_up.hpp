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

// The objects of `population` below min_altitude_m, in population order, and their removal flags
// (flags.size() == population.size(); pass them to Population::remove_flagged).
std::vector<BurnUp> find_burn_ups(const Population& population, double min_altitude_m, double time_s,
                                  std::vector<char>& flags);

}  // namespace kessler
