// A conjunction scan shared out among the ranks of an MPI run: every rank computes the step's boxes and
// cell keys over the whole population (it holds all of it), sorts and walks its share of the grid's
// regions and runs the narrow phase on the candidate pairs found there (ConjunctionDetector::set_share); the
// encounters of all ranks are then gathered to every rank (MPI_Allgatherv) and put in canonical order. A pair
// belongs to the slot of its first member, so each encounter is found by exactly one rank: the list is
// bitwise the single-process scan's, on every rank.
#pragma once

#include <vector>

#include "core/conjunctions/detector.hpp"
#include "core/distributed/rank_team.hpp"
#include "core/simulation/simulation_parts.hpp"

namespace kessler::distributed {

class DistributedScanner final : public EncounterScanner {
 public:
  DistributedScanner(const ConjunctionSettings& settings, RankTeam& team);

  void scan(const Population& population, const StepEnds& step, std::vector<Encounter>& out) override;
  double last_grid_s() const override { return detector_.last_grid_s(); }
  // No copies: the loop then scans one step at a time, so every rank makes its collective calls in the
  // same order (a propagation, then that step's scan).
  std::unique_ptr<EncounterScanner> another() const override { return nullptr; }

  // Seconds of the scans spent in this rank's own detector.
  double compute_s() const { return compute_s_; }

 private:
  RankTeam& team_;
  ConjunctionDetector detector_;
  std::vector<Encounter> mine_;
  std::vector<int> bytes_of_rank_, displacements_;
  std::vector<long long> shapes_;  // per rank: encounter bytes, grid slots, team size, occupied cells
  double compute_s_ = 0.0;
};

}  // namespace kessler::distributed
