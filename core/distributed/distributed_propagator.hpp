// A propagator whose objects are shared out among the ranks of an MPI run: each rank steps its run of
// object indices (decomposition.hpp) with its own inner propagator (OpenMP over its threads), then every
// rank receives every other rank's new states (and burn-up flags) by MPI_Allgatherv. Every rank holds
// the whole population afterwards, as a single process would.
//
// Each object's step depends on that object alone (propagator.hpp), so the states are bitwise those of
// one process stepping all objects, whatever the rank and thread counts.
#pragma once

#include <memory>
#include <vector>

#include "core/distributed/decomposition.hpp"
#include "core/distributed/rank_team.hpp"
#include "core/integration/propagator.hpp"

namespace kessler::distributed {

class DistributedPropagator final : public Propagator {
 public:
  // inner: the scenario's propagator (SymplecticPropagator, Sgp4Propagator), which must read only the
  // ids, states and area-to-mass ratios of the objects it steps (both do).
  DistributedPropagator(std::unique_ptr<Propagator> inner, RankTeam& team);

  void step(Population& population, double t_start_s, double dt_s) override;
  void step_with(Population& population, double t_start_s, double dt_s, const StepRequest& request) override;
  bool takes_new_objects() const override { return inner_->takes_new_objects(); }

  // Seconds of the steps spent in the inner propagator on this rank.
  double compute_s() const { return compute_s_; }

 private:
  // The run's objects copied into slice_, and the slice's new states back into `to` from index begin.
  void copy_in(const Population& population, std::size_t begin, std::size_t end);
  void copy_out(StateArrays& to, std::size_t begin) const;
  // Every rank's run of `column` to every rank, in place.
  void gather_column(void* column, MPI_Datatype type, const GatherLayout& layout);

  std::unique_ptr<Propagator> inner_;
  RankTeam& team_;
  Population slice_;
  std::vector<char> slice_flags_;
  GatherLayout layout_;  // for layout_objects_ objects
  std::size_t layout_objects_ = 0;
  double compute_s_ = 0.0;
};

}  // namespace kessler::distributed
