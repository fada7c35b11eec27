// Conjunction detection over one step: broad phase on a grid, narrow phase (linear or Hermite), the
// paper's status rules, canonical output order.
#pragma once

#include <atomic>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "core/conjunctions/broad_phase_grid.hpp"
#include "core/conjunctions/encounter.hpp"
#include "core/integration/propagator.hpp"
#include "core/parallel/walk_sharing.hpp"

namespace kessler {

class ConjunctionDetector {
 public:
  // grid: how the broad phase shares out its work (benchmarks time other regions of space); it never
  // changes the encounters.
  explicit ConjunctionDetector(const ConjunctionSettings& settings, const GridSettings& grid = {});

  // The problem with these settings for a step of dt_s, naming the field ("kappa_max",
  // "screening_distance_m", "dt_s"), or nullopt.
  static std::optional<std::string> validate(const ConjunctionSettings& settings, double dt_s);

  // Every encounter of the step (local minima of distance within the threshold, each reported once
  // across steps), appended to `out` in canonical order. Parallel with OpenMP; the output is bitwise
  // identical for any thread count.
  void scan(const Population& population, const StepEnds& step, std::vector<Encounter>& out);

  // Sort and walk only part `part` of `parts` of the grid (the partitions of its regions part / parts
  // to (part + 1) / parts, BroadPhaseGrid::set_share; and oversized objects o with o % parts == part):
  // the encounters of the parts' scans together are exactly those of a whole scan, each in one part (a
  // candidate pair belongs to the slot of its first member). The parts' grids must be laid out alike:
  // each part's detector scans the same steps on teams of the same size, and with parts > 1 no measured
  // cost moves the grid's region borders or chunks (grid_balance.hpp; only the balance between threads
  // suffers); the cells coarsen only when each part is told all parts' occupied cells after each scan
  // (set_all_parts_occupied). Default: part 0 of 1.
  void set_share(std::size_t part, std::size_t parts);

  // Seconds of the last scan spent in the broad phase (grid build and candidate pairs, until the last
  // thread has its candidates) and the rest (narrow phase, merge, sort).
  double last_grid_s() const { return last_grid_s_; }
  double last_narrow_s() const { return last_narrow_s_; }
  // Candidate pairs the broad phase produced in the last scan.
  std::size_t last_candidate_pairs() const { return last_candidate_pairs_; }
  // The team OpenMP gave the last scan (1 below kParallelMinimumObjects): a shared scan's parts must
  // have had the same (set_share).
  std::size_t last_team_size() const { return last_team_size_; }
  // The broad phase's grid (its cell size and build counts, for benchmarks).
  const BroadPhaseGrid& grid() const { return grid_; }
  // A shared scan (set_share): the occupied cells this part sorted in its last scan, and their sum over
  // all parts, for the next scan's cells (BroadPhaseGrid::set_all_parts_occupied).
  std::size_t sorted_occupied_cells() const { return grid_.sorted_occupied_cells(); }
  void set_all_parts_occupied(std::size_t cells) { grid_.set_all_parts_occupied(cells); }

 private:
  ConjunctionSettings settings_;
  // The step the settings were last checked for (a check builds a string stream: once, not every step).
  double validated_dt_s_ = std::numeric_limits<double>::quiet_NaN();  // none yet
  double last_grid_s_ = 0.0;
  double last_narrow_s_ = 0.0;
  std::size_t last_candidate_pairs_ = 0;
  std::size_t last_team_size_ = 0;
  // Whether the next scan tests candidates on hulls first: worth it where candidate pairs are many per
  // object (dense populations, long steps), decided from the last scan. Results never depend on it.
  bool use_hulls_ = false;

  // Narrow phase of one candidate pair (population indices); appends its encounters.
  void examine_pair(const Population& population, const StepEnds& step, std::size_t i, std::size_t j,
                    std::vector<Encounter>& found) const;

  // Scratch kept between scans so a step allocates nothing once warm.
  BroadPhaseGrid grid_;
  // One thread's lists, a cache line of its own: each push_back writes the vector's end pointer, and
  // two threads' pointers on one line would pass that line between their cores on every pair.
  struct alignas(64) ThreadLists {
    std::vector<CandidatePair> candidates;
    std::vector<Encounter> events;
    double collected_at = 0.0;  // when its candidates were complete
    // The slots it walked of its own region and of others'; per thread of the team, the seconds it
    // walked of that thread's slots (its own: walk_s_of[t]).
    std::size_t own_slots = 0, helped_slots = 0;
    std::vector<double> walk_s_of;
  };
  std::vector<ThreadLists> per_thread_;
  // Per thread: how many of the slots it sorted have been claimed for the walk (by it or by others).
  struct alignas(64) WalkCursor {
    std::atomic<std::size_t> claimed{0};
  };
  std::vector<WalkCursor> walk_cursors_;
  WalkSharing sharing_;                // whether threads help walk each other's regions (walk_sharing.hpp)
  std::vector<double> region_cost_s_;  // scratch: each region's cost in the last scan
};

}  // namespace kessler
