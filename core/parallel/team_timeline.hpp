// Where each thread of a parallel region spends a run: its work segments and its waits at barriers,
// summed over the steps. It tells the cost of many threads apart (forks, barriers, an uneven share)
// from the cost of the work. A part handed no timeline (null, the default) keeps none; each segment of
// one that is kept costs one clock read per thread.
#pragma once

#include <omp.h>

#include <algorithm>
#include <array>
#include <cstddef>
#include <string>
#include <utility>
#include <vector>

namespace kessler {

class TeamTimeline {
 public:
  static constexpr int kMaxSegments = 16;

  // The segments' names, in order; segment 0 is the fork (region start to the thread's first line), the
  // last one the join (the thread's last mark to the region's end).
  explicit TeamTimeline(std::vector<std::string> segments) : names_(std::move(segments)) {}

  // The master, just before the fork.
  void region_start(std::size_t team) {
    if (threads_.size() < team) threads_.resize(team);
    team_ = team;
    start_ = omp_get_wtime();
  }
  // Each thread, first thing inside the region.
  void enter(std::size_t t) {
    if (t >= threads_.size()) return;
    PerThread& me = threads_[t];
    me.last = omp_get_wtime();
    me.sum[0] += me.last - start_;
  }
  // Each thread, at the end of segment `s`.
  void mark(std::size_t t, int s) {
    if (t >= threads_.size()) return;
    PerThread& me = threads_[t];
    const double now = omp_get_wtime();
    me.sum[s] += now - me.last;
    me.last = now;
  }
  // The master, just after the join.
  void region_end() {
    const double now = omp_get_wtime();
    const int join = static_cast<int>(names_.size()) - 1;
    for (std::size_t t = 0; t < team_; ++t) threads_[t].sum[join] += now - threads_[t].last;
  }

  const std::vector<std::string>& segments() const { return names_; }
  // Segment s's seconds for each thread, summed over the run.
  std::vector<double> per_thread(int s) const {
    std::vector<double> seconds;
    for (const PerThread& p : threads_) seconds.push_back(p.sum[s]);
    return seconds;
  }
  // The same: the mean and the largest over the threads.
  std::pair<double, double> mean_and_max(int s) const {
    const std::vector<double> seconds = per_thread(s);
    if (seconds.empty()) return {0.0, 0.0};
    double sum = 0.0;
    for (const double t : seconds) sum += t;
    return {sum / static_cast<double>(seconds.size()), *std::max_element(seconds.begin(), seconds.end())};
  }

 private:
  struct alignas(64) PerThread {  // one thread's lines only
    double last = 0.0;
    std::array<double, kMaxSegments> sum{};
  };
  std::vector<std::string> names_;
  std::vector<PerThread> threads_;
  std::size_t team_ = 0;
  double start_ = 0.0;
};

// The segments of the step's parallel regions: the propagator's, the detector's, and the steps in
// flight's (core/simulation/steps_in_flight.hpp: each thread's scans of whole steps, and its wait for
// the last one).
enum PropagatorSegment { kPropFork, kPropBlocks, kPropJoin };
enum DetectorSegment {
  kDetFork,
  kDetGrow,
  kDetEdges,
  kDetKeys,
  kDetScatter,
  kDetWait,    // the build's barrier
  kDetLayout,  // after it: keys and scatter again if the guessed cell was too small, the slot layout
  kDetSort,
  kDetWalk,
  kDetNarrow,
  kDetJoin
};
enum FlightSegment { kFlightFork, kFlightScans, kFlightJoin };

// The timelines of a run's parallel regions, owned by whoever wants phase times (kessler-bench run
// --phase-times) and handed to the parts: the propagator at construction, the steps in flight through
// SimulationParts, and a step's scan through StepEnds::timeline (null for steps scanned in flight,
// which run side by side while a timeline follows one team at a time).
struct PhaseTimelines {
  TeamTimeline propagator{{"fork", "blocks", "join"}};
  TeamTimeline detector{
      {"fork", "grow", "edges", "keys", "scatter", "wait", "layout", "sort", "walk", "narrow", "join"}};
  TeamTimeline flight{{"fork", "scans", "join"}};
};

}  // namespace kessler
