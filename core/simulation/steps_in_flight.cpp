#include "core/simulation/steps_in_flight.hpp"

#include <omp.h>

#include <algorithm>
#include <exception>
#include <stdexcept>
#include <utility>

#include "core/parallel/team_timeline.hpp"

namespace kessler {

StepsInFlight::StepsInFlight(EncounterScanner& first, std::size_t at_once, std::size_t objects,
                             std::size_t threads, PhaseTimelines* timelines)
    : scanners_{&first}, timelines_(timelines) {
  const std::size_t wanted = at_once > 0 ? at_once : steps_in_flight_for(objects, threads);
  bool copies = true;  // whether `first` offers copies (else one step at a time)
  while (copies && scanners_.size() < std::min(wanted, threads)) {
    std::unique_ptr<EncounterScanner> copy = first.another();
    copies = copy != nullptr;
    if (copies) {
      scanners_.push_back(copy.get());
      copies_.push_back(std::move(copy));
    }
  }
  capacity_ = copies ? wanted : 1;
  starts_.resize(capacity_);
}

StepRequest StepsInFlight::request_for_next(StepRequest base, bool last) {
  if (full()) throw std::logic_error("StepsInFlight: no room for another step");
  const std::size_t j = steps_.size();
  if (j == 0) base.start_out = &starts_[0];
  if (!last && j + 1 < capacity()) base.end_out = &starts_[j + 1];
  return base;
}

void StepsInFlight::push(double t_start_s, double dt_s, const ChunkLayout* chunks) {
  steps_.push_back({t_start_s, dt_s, chunks});
}

void StepsInFlight::restart() {
  steps_.clear();
}

const StateArrays& StepsInFlight::end_of(std::size_t j, const Population& population) const {
  return j + 1 < steps_.size() ? starts_[j + 1] : population.state;
}

void StepsInFlight::scan(const Population& population, std::vector<std::vector<Encounter>>& out) {
  const std::size_t m = steps_.size();
  out.resize(std::max(out.size(), m));
  const double start = omp_get_wtime();
  double grid_share = 0.0;
  if (m == 1) {
    // One step: its scanner's own team, each thread reading the chunk its core propagated.
    const HeldStep& h = steps_[0];
    const StepEnds ends{h.t_start_s,       h.dt_s,   &starts_[0],
                        &population.state, h.chunks, timelines_ ? &timelines_->detector : nullptr};
    scanners_[0]->scan(population, ends, out[0]);
    const double scan_s = omp_get_wtime() - start;
    grid_share = scan_s > 0.0 ? std::min(1.0, scanners_[0]->last_grid_s() / scan_s) : 0.0;
  } else if (m > 1) {
    std::vector<double> shares(m, 0.0);
    std::vector<std::exception_ptr> failures(m);
    const int threads =
        static_cast<int>(std::min({m, scanners_.size(), static_cast<std::size_t>(omp_get_max_threads())}));
    TeamTimeline* const timeline = timelines_ ? &timelines_->flight : nullptr;
    if (timeline) timeline->region_start(static_cast<std::size_t>(threads));
#pragma omp parallel num_threads(threads)
    {
      const std::size_t t = static_cast<std::size_t>(omp_get_thread_num());
      if (timeline) timeline->enter(t);
      // Each scan on a team of one (its parallel regions nest inside this one), with no timeline (the
      // scans run side by side, and a timeline follows one team), and with this thread's scanner: its
      // grid (megabytes of scratch) stays in one core's caches. The steps go to the threads as they
      // come free, so a core slowed by other load scans fewer.
      omp_set_num_threads(1);
      EncounterScanner& scanner = *scanners_[t];
#pragma omp for schedule(dynamic, 1)
      for (std::size_t j = 0; j < m; ++j) {
        const HeldStep& h = steps_[j];
        // No chunks: one thread reads every object's states.
        const StepEnds ends{h.t_start_s, h.dt_s, &starts_[j], &end_of(j, population), nullptr};
        const double scan_start = omp_get_wtime();
        // An exception may not leave the parallel region: the earliest step's is thrown after it.
        try {
          scanner.scan(population, ends, out[j]);
        } catch (...) {
          failures[j] = std::current_exception();
        }
        const double scan_s = omp_get_wtime() - scan_start;
        shares[j] = scan_s > 0.0 ? std::min(1.0, scanner.last_grid_s() / scan_s) : 0.0;
      }
      if (timeline) timeline->mark(t, kFlightScans);
    }
    if (timeline) timeline->region_end();
    for (const std::exception_ptr& failure : failures)
      if (failure) std::rethrow_exception(failure);
    for (const double s : shares) grid_share += s / static_cast<double>(m);
  }
  last_scan_s_ = omp_get_wtime() - start;
  last_grid_s_ = last_scan_s_ * grid_share;
}

}  // namespace kessler
