// What leaves a running simulation: the one small interface the service and the tests implement.
//
// Every event carries a sequence number, assigned by the simulation in a deterministic order (step by
// step; within a step: encounters in canonical order, then burn-ups by id, then breakups (collisions in
// canonical order, then scheduled ones in schedule order), then lifecycle events (ends of life, then
// launches), then progress). A run resumed
// from a checkpoint re-emits the events after the checkpoint's sequence number with the same numbers and
// the same contents, so a consumer can store idempotently by sequence number.
#pragma once

#include <concepts>
#include <cstdint>
#include <memory>
#include <string>
#include <type_traits>
#include <vector>

#include "core/conjunctions/encounter.hpp"
#include "core/integration/burn_up.hpp"
#include "core/population/population.hpp"
#include "core/simulation/breakups.hpp"
#include "core/simulation/snapshots.hpp"
#include "core/simulation/traffic.hpp"

namespace kessler {

// Objects alive by type; fragments are the objects breakups made (Population::breakup_id != 0), the
// other counts are the catalog's types.
struct ObjectCounts {
  std::uint64_t payload = 0, rocket_body = 0, debris = 0, unknown = 0, fragments = 0;
};

struct Progress {
  std::int64_t step = 0;  // steps completed
  std::int64_t total_steps = 0;
  double sim_time_s = 0.0;  // seconds since the scenario epoch
  std::uint64_t objects_alive = 0;
  ObjectCounts objects_by_type;     // sums to objects_alive
  std::uint64_t events_so_far = 0;  // encounters + burn-ups + breakups emitted
  double wall_s = 0.0;              // wall time of this run so far (not deterministic)
  double eta_s = 0.0;               // estimated wall time left
};

// Seconds spent per phase, as the paper's runtime breakdown.
struct PhaseTimers {
  double integrator_s = 0.0;
  double burn_up_s = 0.0;
  double grid_s = 0.0;       // broad phase: container update
  double detection_s = 0.0;  // narrow phase and event assembly
  double output_s = 0.0;     // handing events to the sink
  double checkpoint_s = 0.0;
  double total_s = 0.0;
};

// What a run has counted so far: kept by the loop, carried by a checkpoint, reported in the summary.
struct RunCounters {
  std::uint64_t events = 0;        // encounters (all kinds) + burn-ups + breakups + lifecycle events
  std::uint64_t conjunctions = 0;  // conjunctions and collisions (a collision is also a conjunction)
  std::uint64_t collisions = 0;
  std::uint64_t evasions = 0;
  std::uint64_t burn_ups = 0;
  std::uint64_t objects_initial = 0;
};

// Every counter, once, in the checkpoint's order: f(name, member).
template <class C, class F>  // C: RunCounters or const RunCounters
requires std::same_as<std::remove_const_t<C>, RunCounters>
void for_each_counter(C& c, F&& f) {
  f("events", c.events);
  f("conjunctions", c.conjunctions);
  f("collisions", c.collisions);
  f("evasions", c.evasions);
  f("burn_ups", c.burn_ups);
  f("objects_initial", c.objects_initial);
}

// The counters are a base, so hosts read summary.events directly.
struct RunSummary : RunCounters {
  std::int64_t steps = 0;
  double sim_time_s = 0.0;
  std::uint64_t objects_final = 0;
  std::string events_digest;  // hex hash over every event in sequence order, bit for bit
  std::string state_digest;   // hex hash over the final ids and states, bit for bit
  PhaseTimers timers;
  bool cancelled = false;
  // Stopped by RunControl::stop_after_checkpoint: not finished, resumable from the last checkpoint
  // (on_finished is not called then).
  bool stopped_at_checkpoint = false;
};

// The core calls the sink synchronously from the loop's thread, at step boundaries. A sink must return
// promptly: it may buffer (bounded) and hand over to another thread, but it must not drop an event; a
// sink that cannot keep up should block briefly (back-pressure) rather than lose anything. Encounters and
// burn-ups of one step are delivered before that step's progress, and every event of a checkpoint's
// steps before that checkpoint. on_finished or on_failed comes last, once (neither after a stop at a
// checkpoint). Sequence numbers start at 1 and have no gaps.
class EventSink {
 public:
  virtual ~EventSink() = default;
  virtual void on_encounter(std::uint64_t seq, const Encounter& encounter) = 0;
  virtual void on_burn_up(std::uint64_t seq, const BurnUp& burn_up) = 0;
  virtual void on_progress(std::uint64_t seq, const Progress& progress) = 0;
  // A breakup (SimulationConfig::breakups, scheduled or a collision); only runs with breakups enabled
  // have them.
  virtual void on_breakup(std::uint64_t /*seq*/, const BreakupReport& /*breakup*/) {}
  // A launch, end of life or disposal (SimulationConfig::traffic); only runs with traffic have them.
  virtual void on_lifecycle(std::uint64_t /*seq*/, const LifecycleReport& /*event*/) {}
  // The population at a boundary (SimulationConfig::snapshot_every_steps), after that boundary's
  // events and progress. No sequence number and not in the events digest (snapshots.hpp); a resumed
  // run hands over again the snapshots after its checkpoint's step, so store them by step.
  virtual void on_snapshot(const std::shared_ptr<const PopulationSnapshot>& /*snapshot*/) {}
  // A checkpoint, complete and self-contained: every event with a sequence number <= last_seq was
  // handed over before it. Store it atomically; a run resumes from these bytes.
  virtual void on_checkpoint(std::uint64_t last_seq, std::int64_t step, const std::string& bytes) = 0;
  virtual void on_finished(const RunSummary& summary) = 0;
  virtual void on_failed(const std::string& reason) = 0;
};

// Hears every event and keeps none: for a run whose summary is all that is wanted (a rank that does not
// print, an ensemble member, a benchmark); derive to keep one kind.
class NullSink : public EventSink {
 public:
  void on_encounter(std::uint64_t, const Encounter&) override {}
  void on_burn_up(std::uint64_t, const BurnUp&) override {}
  void on_progress(std::uint64_t, const Progress&) override {}
  void on_checkpoint(std::uint64_t, std::int64_t, const std::string&) override {}
  void on_finished(const RunSummary&) override {}
  void on_failed(const std::string&) override {}
};

}  // namespace kessler
