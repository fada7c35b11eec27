// Breakups scheduled in a run's configuration (off by default): at the step boundary an event falls on,
// its parents leave the population and the NASA Standard Breakup Model's fragments (core/breakup/) join
// it. core/simulation/README.md describes the timing, the fragments' properties and their ids.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "core/breakup/breakup_event.hpp"
#include "core/population/population.hpp"

namespace kessler {

// Fragment ids count up from here, above every catalog number (NORAD numbers, alpha-5 included, stay
// below 340,000; analyst objects below 10^6), so a fragment never takes a catalog object's id.
inline constexpr ObjectId kFirstFragmentId = 1'000'000'000;

struct ScheduledBreakup {
  // When: at the end of step `step` (steps completed, >= 1) when set, else at the first step boundary at
  // or after epoch_offset_s seconds from the scenario start (a breakup inside a step happens at its end).
  std::optional<std::int64_t> step;
  double epoch_offset_s = 0.0;
  BreakupKind kind = BreakupKind::kExplosion;
  std::vector<ObjectId> object_ids;        // one (explosion) or two (collision)
  std::optional<double> impact_speed_m_s;  // collisions: unset, the parents' relative speed
  std::vector<double> masses_kg;           // empty: the population's masses; else one per object
};

struct BreakupSettings {
  bool enabled = false;
  double min_characteristic_length_m = 0.10;
  bool mass_conservation = true;
  double explosion_scale = 1.0;  // S in N = 6 S Lc^-1.6
  std::uint64_t max_fragments_per_event = 1'000'000;
  std::vector<ScheduledBreakup> scheduled;
};

// What one breakup did, as the event stream reports it.
struct BreakupReport {
  std::uint64_t event_index = 0;  // into BreakupSettings::scheduled
  double time_s = 0.0;            // the step boundary it happened at
  BreakupKind kind = BreakupKind::kExplosion;
  std::vector<ObjectId> parents;
  bool catastrophic = false;
  double specific_energy_j_per_g = 0.0;  // collisions; explosions 0
  std::uint64_t fragment_count = 0;
  double fragment_mass_kg = 0.0;
  ObjectId first_id = 0, last_id = 0;  // the new ids, first_id..last_id; both 0 when none
};

// The boundary step (steps completed) of each scheduled event, with dt_s.
std::int64_t breakup_boundary_step(const ScheduledBreakup& b, double dt_s);

// The scheduled events due at boundary `step`, in schedule order.
std::vector<std::size_t> breakups_due(const BreakupSettings& settings, std::int64_t step, double dt_s);

// The first boundary after `step` (steps completed) with a breakup due; nullopt when none.
std::optional<std::int64_t> next_breakup_step(const BreakupSettings& settings, std::int64_t step,
                                              double dt_s);

// Applies scheduled event `index` to `population` at time_s: the parents' states are their states now.
// Fragments take ids from next_id on (advanced past them), in draw order, and are appended; catastrophic
// parents are removed, a non-catastrophic collision's target stays with the remnant's mass and velocity.
// A parent not in the population (burnt up, broken up before): nothing happens, nullopt.
std::optional<BreakupReport> apply_scheduled_breakup(const BreakupSettings& settings, std::size_t index,
                                                     std::uint64_t seed, double time_s,
                                                     Population& population, ObjectId& next_id);

}  // namespace kessler
