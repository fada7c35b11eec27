// The Iridium 33 / Cosmos 2251 collision of 2009-02-10 through the core loop, for the benches that
// follow its clouds (breakup-decay, decay-history).
//
// The parents come from their last element sets before the collision (tests/data/iridium_cosmos/, as
// tests/breakup/iridium_cosmos_test.cpp reads them), moved by SGP4 to the start: one step of dt before the
// time of closest approach that test finds (16:55:59.796 UTC). Iridium 33 (NORAD 24946) 560 kg, 1.5 m;
// Cosmos 2251 (22675) 950 kg, 2.0 m (the radius is half the size; drag Cd A/m with Cd 2.2 and A = pi r^2).
// A ScheduledBreakup of kind kCollision at the end of step 1 (the closest approach) with masses_kg
// {560, 950} breaks them up with the NASA Standard Breakup Model at Lc >= lc_min; the numerical
// propagator with the given force model, burn-up at 150 km, conjunctions off.
#pragma once

#include <cstdint>
#include <map>
#include <string>

#include "core/physics/force_model_settings.hpp"
#include "core/simulation/simulation.hpp"

namespace kessler::bench {

inline constexpr ObjectId kIridium33 = 24946, kCosmos2251 = 22675;

struct CloudRunOptions {
  UtcEpoch to;
  double dt_s = 60.0;
  double lc_min_m = 0.10;
  int threads = 1;
  std::uint64_t seed = 20090210;
  std::string tle_path;  // the two last element sets
  ForceModelSettings force_model;
};

struct CloudRun {
  UtcEpoch start;                                      // one step before the closest approach
  std::map<ObjectId, ObjectId> parent;                 // fragment id -> parent id
  std::map<ObjectId, double> burn_up_s;                // object id -> burn-up time [s since the start]
  std::map<ObjectId, double> drag_area_to_mass_m2_kg;  // fragment id -> Cd A/m (Cd 2.2, the SBM's A/m)
  double breakup_time_s = 0.0, specific_energy_j_per_g = 0.0, end_s = 0.0, wall_s = 0.0;
  bool catastrophic = false;
  std::int64_t steps = 0;
  std::size_t alive_at_end = 0;
};

// The closest approach of the two parents (UTC).
UtcEpoch iridium_cosmos_tca();
// The run; throws std::runtime_error when the element sets cannot be read or the run fails.
CloudRun run_iridium_cosmos_cloud(const CloudRunOptions& options);

struct CloudCounts {
  std::int64_t iridium = 0, cosmos = 0;
};
// Fragments of each parent not burnt up by t_s.
CloudCounts cloud_on_orbit_at(const CloudRun& run, double t_s);

}  // namespace kessler::bench
