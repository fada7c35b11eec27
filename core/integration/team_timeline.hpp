// Where each thread of a parallel region spends a run: its work segments and its waits at barriers,
// summed over the steps. It tells the cost of many threads apart (forks, barriers, an uneven share)
// from the cost of the work. Off by default (a benchmark turns it on): when on, each segment costs one
// clock read per thread.
#pragma once

#include <omp.h>

#include <algorithm>
#include <array>
#include <atomic>
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

  void enable(bool on) { enabled_.store(on, std::memory_order_relaxed); }
  bool enabled() const { return enabled_.load(std::memory_order_relaxed); }
  void reset() { threads_.clear(); }

  // The master, just before the fork.
  void region_start(std::size_t team) {
    if (!enabled()) return;
    if (threads_.size() < team) threads_.resize(team);
    team_ = team;
    start_ = omp_get_wtime();
  }
  // Each thread, first thing inside the region.
  void enter(std::size_t t) {
    if (!enabled() || t >= threads_.size()) return;
    PerThread& me = threads_[t];
    me.last = omp_get_wtime();
    me.sum[0] += me.last - start_;
  }
  // Each thread, at the end of segment `s`.
  void mark(std::size_t t, int s) {
    if (!enabled() || t >= threads_.size()) return;
    PerThread& me = threads_[t];
    const double now = omp_get_wtime();
    me.sum[s] += now - me.last;
    me.last = now;
  }
  // The master, just after the join.
  void region_end() {
    if (!enabled()) return;
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
  std::atomic<bool> enabled_{false};
};

// The timelines of the step's two parallel regions (process-wide: for benchmarks, one run at a time).
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
inline TeamTimeline& propagator_timeline() {
  static TeamTimeline timeline({"fork", "blocks", "join"});
  return timeline;
}
// Set on a thread while it scans one of several steps in flight (core/simulation/steps_in_flight.hpp):
// those scans run side by side, each on a team of one, and keep no timeline of their own.
inline thread_local bool scanning_in_flight = false;
inline TeamTimeline& detector_timeline() {
  static TeamTimeline timeline(
      {"fork", "grow", "edges", "keys", "scatter", "wait", "layout", "sort", "walk", "narrow", "join"});
  static TeamTimeline unused({"fork", "join"});  // never enabled
  return scanning_in_flight ? unused : timeline;
}
// Steps in flight: each thread's scans of whole steps, and its wait for the last one.
enum FlightSegment { kFlightFork, kFlightScans, kFlightJoin };
inline TeamTimeline& flight_timeline() {
  static TeamTimeline timeline({"fork", "scans", "join"});
  return timeline;
}

}  // namespace kessler
