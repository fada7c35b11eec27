#include "core/distributed/distributed_propagator.hpp"

#include <algorithm>
#include <stdexcept>
#include <utility>

#include "core/distributed/decomposition.hpp"

namespace kessler::distributed {
namespace {

template <class T>
void copy_run(const std::vector<T>& from, std::size_t begin, std::size_t end, std::vector<T>& to) {
  to.assign(from.begin() + static_cast<std::ptrdiff_t>(begin),
            from.begin() + static_cast<std::ptrdiff_t>(end));
}

template <class T>
void copy_back(const std::vector<T>& from, std::size_t begin, std::vector<T>& to) {
  std::copy(from.begin(), from.end(), to.begin() + static_cast<std::ptrdiff_t>(begin));
}

}  // namespace

DistributedPropagator::DistributedPropagator(std::unique_ptr<Propagator> inner, RankTeam& team)
    : inner_(std::move(inner)), team_(team) {
  if (!inner_) throw std::invalid_argument("DistributedPropagator: an inner propagator is required");
}

void DistributedPropagator::step(Population& population, double t_start_s, double dt_s) {
  step_with(population, t_start_s, dt_s, StepRequest{});
}

void DistributedPropagator::copy_in(const Population& population, std::size_t begin, std::size_t end) {
  copy_run(population.id, begin, end, slice_.id);
  const StateArrays& from = population.state;
  StateArrays& to = slice_.state;
  copy_run(from.x, begin, end, to.x);
  copy_run(from.y, begin, end, to.y);
  copy_run(from.z, begin, end, to.z);
  copy_run(from.vx, begin, end, to.vx);
  copy_run(from.vy, begin, end, to.vy);
  copy_run(from.vz, begin, end, to.vz);
  copy_run(population.drag_area_to_mass_m2_kg, begin, end, slice_.drag_area_to_mass_m2_kg);
  copy_run(population.srp_area_to_mass_m2_kg, begin, end, slice_.srp_area_to_mass_m2_kg);
}

void DistributedPropagator::copy_out(StateArrays& to, std::size_t begin) const {
  const StateArrays& from = slice_.state;
  copy_back(from.x, begin, to.x);
  copy_back(from.y, begin, to.y);
  copy_back(from.z, begin, to.z);
  copy_back(from.vx, begin, to.vx);
  copy_back(from.vy, begin, to.vy);
  copy_back(from.vz, begin, to.vz);
}

void DistributedPropagator::gather_column(void* column, MPI_Datatype type, const GatherLayout& layout) {
  RankTeam::Timed timed(team_);
  MPI_Allgatherv(MPI_IN_PLACE, 0, MPI_DATATYPE_NULL, column, layout.counts.data(),
                 layout.displacements.data(), type, team_.comm());
}

void DistributedPropagator::step_with(Population& population, double t_start_s, double dt_s,
                                      const StepRequest& request) {
  const std::size_t n = population.size();
  const IndexRun run = run_of_rank(n, team_.rank(), team_.ranks());
  // With the start states asked for, the new states are gathered into that buffer, which then trades
  // places with the population's: the start states are where the population's were, with no copy of
  // the whole population on every rank.
  StateArrays* const next = request.start_out;
  if (next != nullptr) next->resize(n);
  // This rank's objects, stepped by the inner propagator; a failure on any rank fails all of them.
  team_.all_or_none([&] {
    const double start = MPI_Wtime();
    copy_in(population, run.begin, run.end);
    StepRequest inner;
    if (request.burn_up_flags != nullptr) {
      inner.burn_up_flags = &slice_flags_;
      inner.burn_up_radius2 = request.burn_up_radius2;
    }
    inner_->step_with(slice_, t_start_s, dt_s, inner);
    copy_out(next != nullptr ? *next : population.state, run.begin);
    compute_s_ += MPI_Wtime() - start;
  });
  // Every rank's new states (and flags) to every rank, in place. (The count was checked against int at
  // the start of the run: check_rank_count.)
  if (layout_objects_ != n || layout_.counts.size() != static_cast<std::size_t>(team_.ranks())) {
    const std::optional<GatherLayout> layout = gather_layout(n, team_.ranks());
    if (!layout) throw std::runtime_error("DistributedPropagator: too many objects for an MPI gather");
    layout_ = *layout;
    layout_objects_ = n;
  }
  StateArrays& state = next != nullptr ? *next : population.state;
  for (std::vector<double>* column : {&state.x, &state.y, &state.z, &state.vx, &state.vy, &state.vz})
    gather_column(column->data(), MPI_DOUBLE, layout_);
  if (next != nullptr) std::swap(population.state, *next);
  if (request.burn_up_flags != nullptr) {
    std::vector<char>& flags = *request.burn_up_flags;
    flags.resize(n);
    if (run.size() > 0) copy_back(slice_flags_, run.begin, flags);
    gather_column(flags.data(), MPI_CHAR, layout_);
  }
  if (request.end_out != nullptr) *request.end_out = population.state;
}

}  // namespace kessler::distributed
