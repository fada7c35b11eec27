// Conjunction scans of consecutive steps side by side: a team of T threads propagates T steps one after
// the other (each step in parallel over objects, as always), then scans them at once, each step whole on
// one thread, with that thread's own scanner.
//
// Why: a step's scan split over a team needs its threads to exchange records (each core propagated a
// chunk of the catalog, but sorts and walks a region of space), and with two cores far apart that
// exchange, the barriers and the uneven regions cost a 2-thread scan a fifth of its time. A whole step
// on one core has none of them: it reads its step's states, half of them from the other core's caches,
// in sequence, and writes only its own grid. What it costs: the propagator then writes lines the other
// core has read (core/conjunctions/README.md, "Steps in flight").
//
// Results: a scan reads only its step's two ends and the population, so each step's encounters are the
// same bits whichever thread scans it and however many steps are in flight. The population may change
// between batches only (the loop ends a batch at the step where objects burn up).
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "core/conjunctions/encounter.hpp"
#include "core/integration/propagator.hpp"
#include "core/population/population.hpp"
#include "core/simulation/simulation_parts.hpp"

namespace kessler {

struct PhaseTimelines;

// Steps in flight pay off only while a step is small. The propagator then writes lines that another
// core read in its scans (the states and their copies), and for larger populations that costs more than
// the scans save: on the 2-core development host, whole runs on 2 threads against one step at a time
// were even at 16,710 and 20,000 objects (detection alone 1.87x against 1.58x), 5 % slower at 40,000, 8 %
// at 80,000 and 13 % at 320,000 (core/conjunctions/README.md, "Steps in flight").
inline constexpr std::size_t kFlightMaxObjects = 32768;
// They cost memory too: each thread beyond the first has a detector (its grid's scratch) and each step
// beyond the first a copy of the states, ~310 bytes per object together (leo-19647 at peak: 471 B per
// object on one thread, 784 with two steps in flight on two).
inline constexpr std::size_t kFlightBytesPerObjectPerStep = 400;
inline constexpr std::size_t kFlightMemoryBudgetBytes = std::size_t{256} << 20;

// The steps to scan at once when the configuration leaves it open: one per thread for populations up
// to kFlightMaxObjects whose extra memory stays within the budget; else one at a time on the whole team
// (fewer steps than threads would leave threads idle in the scans).
inline std::size_t steps_in_flight_for(std::size_t objects, std::size_t threads) {
  if (threads < 2 || objects > kFlightMaxObjects) return 1;
  const std::size_t extra = objects * (threads - 1) * kFlightBytesPerObjectPerStep;
  return extra <= kFlightMemoryBudgetBytes ? threads : 1;
}

class StepsInFlight {
 public:
  // Up to `at_once` steps at once (0: steps_in_flight_for(objects, threads)), scanned by up to `threads`
  // threads, each with a scanner of its own: `first` (the caller's) and copies of it
  // (EncounterScanner::another(), owned here). A scanner that offers no copies scans one step at a
  // time. A batch of one step is scanned by `first` on its own team, reading states in the propagator's
  // chunks (StepEnds::chunks). timelines: where the batches' threads and a lone step's scan are timed
  // (null: untimed).
  StepsInFlight(EncounterScanner& first, std::size_t at_once, std::size_t objects, std::size_t threads,
                PhaseTimelines* timelines = nullptr);

  std::size_t capacity() const { return capacity_; }
  // `first`, then its copies.
  const std::vector<EncounterScanner*>& scanners() const { return scanners_; }
  std::size_t size() const { return steps_.size(); }
  bool full() const { return steps_.size() == capacity_; }

  // The propagator's request for the next step: `base` (burn-up flags), and copies of the states the
  // scans will need: the batch's first step copies its start states, every step but the last its end
  // states (the next step's start). last: no step follows in this batch (the caller knows when the batch
  // is full or ends at a checkpoint or at the run's end; where a burn-up ends it, one copy goes unread).
  StepRequest request_for_next(StepRequest base, bool last);
  // Records the step just propagated with request_for_next's request.
  void push(double t_start_s, double dt_s, const ChunkLayout* chunks);
  // Scans every step held, step j's encounters appended to out[j] (resized to size()) in canonical
  // order. `population` is the one all held steps were propagated with, its states the last step's end.
  void scan(const Population& population, std::vector<std::vector<Encounter>>& out);
  // Forgets the held steps: the next step starts a new batch (and copies its start states again, so the
  // population may change in between).
  void restart();

  // Seconds of the last scan() (wall) and the part of it in the broad phase (each scanner's share of
  // its own time, averaged over the steps).
  double last_scan_s() const { return last_scan_s_; }
  double last_grid_s() const { return last_grid_s_; }
  // The start states of step j (> 0) of the last batch: the end of step j - 1, bit for bit. Kept until
  // the next batch's first step, so that a batch cut short (a collision that breaks up in an earlier
  // step) can go back to that boundary.
  const StateArrays& start_of(std::size_t j) const { return starts_.at(j); }

 private:
  struct HeldStep {
    double t_start_s, dt_s;
    const ChunkLayout* chunks;
  };
  // Step j's end states: the next step's start, and the population's own states for the last step.
  const StateArrays& end_of(std::size_t j, const Population& population) const;

  std::vector<std::unique_ptr<EncounterScanner>> copies_;
  std::vector<EncounterScanner*> scanners_;
  std::size_t capacity_ = 1;
  // starts_[j]: the start states of the batch's step j. The last step's end is the population's states,
  // so a batch of B steps copies B boundaries, as many as one step at a time copies (its starts).
  std::vector<StateArrays> starts_;
  std::vector<HeldStep> steps_;
  PhaseTimelines* timelines_ = nullptr;
  double last_scan_s_ = 0.0, last_grid_s_ = 0.0;
};

}  // namespace kessler
