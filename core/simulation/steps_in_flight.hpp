// Conjunction scans of consecutive steps side by side: a team of T threads propagates T steps one after
// the other (each step in parallel over objects, as always), then scans them at once, each step whole on
// one thread with a scanner of its own.
//
// Why: a step's scan split over a team needs its threads to exchange records (each core propagated a
// chunk of the catalog, but sorts and walks a region of space), and with two cores far apart that
// exchange cost as much as the rest of the scan's excess together (core/conjunctions/README.md, "Steps
// in flight"). A whole step on one core shares nothing while it runs: it reads each state once, in
// sequence, from the core that propagated it, and writes only its own grid.
//
// Results: a scan reads only its step's two ends and the population, so each step's encounters are the
// same bits whichever thread scans it and however many steps are in flight. The population may change
// between batches only (the loop ends a batch at the step where objects burn up).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/conjunctions/encounter.hpp"
#include "core/integration/propagator.hpp"
#include "core/population/population.hpp"
#include "core/simulation/simulation_parts.hpp"

namespace kessler {

class StepsInFlight {
 public:
  // Up to scanners.size() steps at once (one scanner each; the caller owns them). One scanner: the
  // step is scanned by its own team, reading states in the propagator's chunks (StepEnds::chunks).
  explicit StepsInFlight(std::vector<EncounterScanner*> scanners);

  std::size_t capacity() const { return scanners_.size(); }
  std::size_t size() const { return steps_.size(); }
  bool full() const { return steps_.size() == scanners_.size(); }

  // The propagator's request for the next step: `base` (burn-up flags), the step's end states copied
  // into the ring, and, for the first step after restart(), its start states too.
  StepRequest request_for_next(StepRequest base);
  // Records the step just propagated with request_for_next's request.
  void push(double t_start_s, double dt_s, const ChunkLayout* chunks);
  // Scans every step held, step j's encounters appended to out[j] (resized to size()) in canonical
  // order. `population` is the one all held steps were propagated with.
  void scan(const Population& population, std::vector<std::vector<Encounter>>& out);
  // Forgets the held steps: the next step starts a new batch. population_changed: objects were removed or
  // added since the last step, so its start states must be copied afresh rather than read from the ring.
  void restart(bool population_changed);

  // Seconds of the last scan() (wall) and the part of it in the broad phase (each scanner's share of
  // its own time, averaged over the steps).
  double last_scan_s() const { return last_scan_s_; }
  double last_grid_s() const { return last_grid_s_; }

 private:
  struct HeldStep {
    double t_start_s, dt_s;
    const ChunkLayout* chunks;
  };
  StateArrays& slot(std::int64_t boundary) {
    return ring_[static_cast<std::size_t>(boundary) % ring_.size()];
  }

  std::vector<EncounterScanner*> scanners_;
  // Each step boundary's states: boundary k in ring_[k % size]. A batch of B steps reads B + 1.
  std::vector<StateArrays> ring_;
  std::int64_t first_boundary_ = 0;  // the boundary the held steps start at
  bool start_in_ring_ = false;       // whether slot(first_boundary_) holds it already
  std::vector<HeldStep> steps_;
  double last_scan_s_ = 0.0, last_grid_s_ = 0.0;
};

}  // namespace kessler
