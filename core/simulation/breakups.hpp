// Breakups in a run (off by default): scheduled in the configuration (at the step boundary an event
// falls on) or a collision the detector finds (at its time of closest approach). The parents leave the
// population (a non-catastrophic collision's target stays as the remnant) and the NASA Standard Breakup
// Model's fragments (core/breakup/) join it. core/simulation/README.md describes the timing, the
// fragments' properties, their ids and the separation rule.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

#include "core/breakup/breakup_event.hpp"
#include "core/conjunctions/encounter.hpp"
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

// What a collision the detector finds (d <= r1 + r2) does when breakups are enabled.
enum class CollisionResponse : std::uint8_t {
  kFragment = 0,    // both objects break up at the time of closest approach
  kRecordOnly = 1,  // the collision is an event and both fly on (as without breakups)
};

struct BreakupSettings {
  bool enabled = false;
  CollisionResponse on_collision = CollisionResponse::kFragment;
  // The separation rule: for this long after a breakup [s], its fragments (and its remnant) are not
  // screened against each other: they start within metres of one another, and every pair would be a
  // "conjunction" until they part. Afterwards every pair is screened as any other.
  double separation_s = 600.0;
  double min_characteristic_length_m = 0.10;
  bool mass_conservation = true;
  double explosion_scale = 1.0;  // S in N = 6 S Lc^-1.6
  std::uint64_t max_fragments_per_event = 1'000'000;
  std::vector<ScheduledBreakup> scheduled;
};

// One fragment as the event stream reports it (what `kessler fragments` lists).
struct FragmentReport {
  ObjectId id = 0;
  ObjectId parent_id = 0;
  double characteristic_length_m = 0.0;
  double area_to_mass_m2_kg = 0.0;
  double mass_kg = 0.0;
  double delta_v_m_s = 0.0;  // |dv| of the ejection
};

enum class BreakupSource : std::uint8_t {
  kScheduled = 0,  // BreakupSettings::scheduled[scheduled_index]
  kCollision = 1,  // a collision the detector found
};

// What one breakup did, as the event stream reports it.
struct BreakupReport {
  BreakupId breakup_id = 0;  // 1, 2, ... in event order (the key of its random draws)
  BreakupSource source = BreakupSource::kScheduled;
  std::uint64_t event_index = 0;  // scheduled: index into BreakupSettings::scheduled; collision: 0
  double time_s = 0.0;            // scheduled: the step boundary; collision: the time of closest approach
  BreakupKind kind = BreakupKind::kExplosion;
  std::vector<ObjectId> parents;
  bool catastrophic = false;
  double specific_energy_j_per_g = 0.0;  // collisions; explosions 0
  std::uint64_t fragment_count = 0;
  double fragment_mass_kg = 0.0;
  ObjectId first_id = 0, last_id = 0;     // the new ids, first_id..last_id; both 0 when none
  ObjectId remnant_id = 0;                // a non-catastrophic collision's target (it keeps its id); else 0
  std::vector<FragmentReport> fragments;  // first_id..last_id in order
};

// The boundary step (steps completed) of each scheduled event, with dt_s.
std::int64_t breakup_boundary_step(const ScheduledBreakup& b, double dt_s);

// The scheduled events due at boundary `step`, in schedule order.
std::vector<std::size_t> breakups_due(const BreakupSettings& settings, std::int64_t step, double dt_s);

// The first boundary after `step` (steps completed) with a breakup due; nullopt when none.
std::optional<std::int64_t> next_breakup_step(const BreakupSettings& settings, std::int64_t step,
                                              double dt_s);

// A breakup whose objects are still separating: their separation_group is `group` until until_s.
struct SeparatingBreakup {
  BreakupId group = 0;
  double until_s = 0.0;
};

// The run's breakup bookkeeping (kept in the checkpoint): fragment ids and breakup numbers never repeat.
struct BreakupIds {
  ObjectId next_fragment_id = kFirstFragmentId;
  BreakupId next_breakup_id = 1;
  std::vector<SeparatingBreakup> separating;  // in breakup order
};

// The separation rule at the start of a step at t_start_s: the groups whose time is over are cleared
// (their objects' separation_group set to 0) and dropped from ids.separating. Returns whether any was.
bool end_separations(double t_start_s, Population& population, BreakupIds& ids);

// The first step boundary (steps completed) after `step` at which a separation ends; nullopt when none.
std::optional<std::int64_t> next_separation_end_step(const BreakupIds& ids, std::int64_t step, double dt_s);

// Applies scheduled event `index` to `population` at time_s: the parents' states are their states now.
// The model's draws are keyed by (seed, the breakup's number). Fragments take ids from
// ids.next_fragment_id on, in draw order, and are appended; catastrophic parents are removed, a
// non-catastrophic collision's target stays with the remnant's mass and velocity. A parent not in the
// population (burnt up, broken up before): nothing happens, nullopt (and no number is used).
std::optional<BreakupReport> apply_scheduled_breakup(const BreakupSettings& settings, std::size_t index,
                                                     std::uint64_t seed, double time_s,
                                                     Population& population, BreakupIds& ids);

// Brings objects from t_start_s to t_end_s (the loop's propagator; a collision's fragments and remnant
// from the time of closest approach to the end of its step).
using PropagateObjects = std::function<void(Population& objects, double t_start_s, double t_end_s)>;

// A collision the detector found at the end of the step ending at step_end_s: both objects break up
// from their states at the time of closest approach (the encounter's r, v); the fragments (and a
// non-catastrophic collision's remnant) are brought to step_end_s by `propagate` and join the population.
// Either object already gone (an earlier collision of the step): nothing happens, nullopt.
std::optional<BreakupReport> apply_collision_breakup(const BreakupSettings& settings,
                                                     const Encounter& collision, std::uint64_t seed,
                                                     double step_end_s, Population& population,
                                                     BreakupIds& ids, const PropagateObjects& propagate);

}  // namespace kessler
