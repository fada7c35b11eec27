// Launch traffic and mission lifecycles in a run (off by default): the planned objects enter the
// population at their epochs (core/traffic/launch_plan.hpp); an active payload keeps station (its drag
// compensated) until its operational lifetime ends, then post-mission disposal succeeds or fails
// (core/traffic/lifecycle.hpp). core/simulation/README.md describes the timing and the events.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "core/population/population.hpp"
#include "core/traffic/launch_plan.hpp"
#include "core/traffic/lifecycle.hpp"

namespace kessler {

// Launched objects: kFirstLaunchId + their index in TrafficSettings::launches (above the catalog's
// numbers and the breakup fragments' range).
inline constexpr ObjectId kFirstLaunchId = 2'000'000'000;

struct TrafficSettings {
  bool enabled = false;
  std::vector<PlannedObject> launches;  // expand_launch_plan's objects, in epoch order
  DisposalSettings disposal;
  // The population's own active payloads at the start: each keeps station for a remaining lifetime drawn
  // uniformly in (0, this] years from (seed, id, kRemainingLifetime), then retires like a launched one.
  // 0: they are left as they are (active for the whole run, and not station-kept).
  double catalog_active_lifetime_years = 0.0;
};

// An operated object while active: end of its operational lifetime, and its own drag area-to-mass
// (kept here while it keeps station: the population's is 0 then, the drag compensated).
struct ActiveLife {
  ObjectId id = 0;
  double end_of_life_s = 0.0;
  double drag_area_to_mass_m2_kg = 0.0;
  bool keeps_station = false;
};

// What the traffic has done so far; the checkpoint carries it.
struct TrafficState {
  std::uint64_t next_launch = 0;   // index into TrafficSettings::launches
  std::vector<ActiveLife> active;  // by (end_of_life_s, id)
};

enum class LifecycleEventKind : std::uint8_t {
  kLaunch = 0,          // objects first_id..last_id of plan row `row` entered
  kEndOfLife = 1,       // an active payload's lifetime ended: passive from now on
  kDisposal = 2,        // its disposal succeeded: moved to a circular orbit at altitude_m
  kDisposalFailed = 3,  // its disposal failed: left where it is
  kDeorbit = 4,         // its disposal succeeded as a direct de-orbit: it left the population
};

struct LifecycleReport {
  LifecycleEventKind kind = LifecycleEventKind::kLaunch;
  double time_s = 0.0;                 // the step boundary
  ObjectId first_id = 0, last_id = 0;  // launches: the new ids; otherwise the object, twice
  std::uint64_t row = 0;               // launches: the plan row
  double altitude_m = 0.0;             // disposals: the disposal orbit's altitude
};

// At the start of a fresh run: the population's active payloads become station-kept actives with drawn
// remaining lifetimes (TrafficSettings::catalog_active_lifetime_years), by id.
void adopt_catalog_actives(const TrafficSettings& settings, std::uint64_t seed, Population& population,
                           TrafficState& state);

// The boundary (steps completed, >= 1) an object launched at epoch_offset_s enters at.
std::int64_t launch_boundary_step(double epoch_offset_s, double dt_s);

// The first boundary after `step` with a launch or an end of life due; nullopt when none.
std::optional<std::int64_t> next_traffic_step(const TrafficSettings& settings, const TrafficState& state,
                                              std::int64_t step, double dt_s);

// The launches due at boundary `step` join the population (on their elements carried to the boundary
// by two-body motion), one report per plan row; active payloads are listed in state.active.
std::vector<LifecycleReport> launch_due(const TrafficSettings& settings, std::int64_t step, double dt_s,
                                        Population& population, TrafficState& state);

// The actives whose lifetime ends at or before time_s, in (end, id) order: passive, drag restored, then
// disposal drawn (core/traffic/lifecycle.hpp) in the default table atmosphere. Objects no longer in the
// population (burnt up, broken up) are dropped silently.
std::vector<LifecycleReport> retire_due(const TrafficSettings& settings, std::uint64_t seed, double time_s,
                                        double burn_up_altitude_m, Population& population,
                                        TrafficState& state);

}  // namespace kessler
