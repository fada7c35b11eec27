// How the broad-phase grid shares its work out between the threads of a team, from what each thread's
// work cost in the last scans. Only which thread does what depends on it, never a candidate pair.
//   - RegionBalance: where the borders between the regions of space go along x, so that each region
//     holds a share of the objects inverse to its measured cost per slot (its sort and the walks of its
//     slots): quantiles of a histogram of the lower x corners of the last build's boxes.
//   - PassBalance: each thread's chunk of objects for the passes over objects (boxes, keys, counts,
//     scatter): the propagator's chunk (each core reads the states it wrote), moved so that a thread
//     slower at those passes (a busier core) gets fewer objects.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/conjunctions/grid_cells.hpp"
#include "core/parallel/thread_chunks.hpp"

namespace kessler::grid {

// Measured costs that share out the work (the regions' per slot, the passes' per object): one scan's
// weight in the smoothed cost, and the most it may differ from the team's mean (either way: a stalled
// thread, a page fault in one step, must not empty a region or a chunk).
inline constexpr double kCostSmoothing = 0.125;
inline constexpr double kCostSpread = 1.5;

class RegionBalance {
 public:
  // The histogram's bins, and the objects it samples: every kHistogramStride-th.
  static constexpr std::size_t kHistogramBins = 256, kHistogramStride = 4;
  // The first build's bins span the paper's domain.
  static constexpr double kDefaultBinOrigin_m = -1.0e7, kDefaultBinWidth_m = 2.0e7 / kHistogramBins;

  // Sizes it for `regions` regions and teams of up to `team` threads; costs measured for another
  // number of regions are dropped.
  void prepare(std::size_t regions, std::size_t team);
  // Each region's share of the objects: inverse to its cost per slot so far (1 where unmeasured).
  void shares(std::size_t regions, double* shares) const;
  // The borders [m] along x for the given shares from the last build's histogram, and the bins
  // (origin, width) this build's histogram is to use.
  void borders_from_last(std::size_t regions, const double* shares, double* borders_m, double& bin_origin_m,
                         double& bin_width_m) const;
  // The same borders from this build's histogram (all threads' samples, in bins of the given width).
  void borders_from_this(std::size_t regions, std::size_t threads, const double* shares, double bin_origin_m,
                         double bin_width_m, double* borders_m) const;
  // Thread t's sample of the lower x corners lo_x[begin, end) (those not flagged oversized).
  void sample(std::size_t t, const float* lo_x, const char* oversized, std::size_t begin, std::size_t end,
              double bin_origin_m, double bin_width_m);
  // This build's histogram summed over the threads for the next build: thread t's slice of the bins
  // (once every thread has read the last one).
  void sum_slice(std::size_t t, std::size_t threads);
  // The bins this build's histogram is made of, for the next build (once every thread has taken this
  // build's borders).
  void keep_bins(double bin_origin_m, double bin_width_m) {
    hist_origin_m_ = bin_origin_m;
    hist_width_m_ = bin_width_m;
  }
  // The span of the central 99 % of the lower x corners, from bins of bin_width_m.
  static double central_span_m(double bin_width_m);
  // After a scan: each region's cost [s] and its slots. Ignored where a region has no slots or no cost.
  void record(const double* seconds, const std::size_t* slots, std::size_t regions);

 private:
  std::uint32_t summed_bin(std::size_t b, std::size_t threads) const;
  // Per region: its smoothed cost per slot [s] (0: none measured yet), for costed_regions_ regions.
  double cost_per_slot_s_[kMaxRegions] = {};
  std::size_t costed_regions_ = 0;
  // The last build's histogram (summed over the threads), its bins, and each thread's of this build.
  std::vector<std::uint32_t> hist_;
  double hist_origin_m_ = kDefaultBinOrigin_m, hist_width_m_ = kDefaultBinWidth_m;
  std::vector<std::uint32_t> thread_hist_;
};

class PassBalance {
 public:
  // Sizes the per-thread records for teams of up to `team` threads.
  void prepare(std::size_t team) { thread_pass_.resize(team); }
  // Thread t's chunk of the n objects: thread_chunk's (the propagator's layout), each chunk weighted by 1
  // / its thread's smoothed cost per object (the propagator's until measured, and for a team of one).
  // The chunks stay contiguous and in order.
  ThreadChunk chunk(const ChunkLayout* layout, std::size_t n, std::size_t t, std::size_t team) const;
  // Thread t's passes over its chunk in this build.
  void measured(std::size_t t, double seconds, std::size_t objects) { thread_pass_[t] = {seconds, objects}; }
  // After a scan whose team was the one asked for: the costs measured in its build.
  void record(std::size_t team);
  // The same with the given seconds and objects per thread, as if the last build had measured them.
  void record(const double* seconds, const std::size_t* objects, std::size_t team);

 private:
  struct alignas(64) ThreadPass {
    double seconds = 0.0;     // the last build's passes over its chunk
    std::size_t objects = 0;  // in its chunk
  };
  std::vector<ThreadPass> thread_pass_;
  std::vector<double> cost_per_object_s_;  // per thread, smoothed, for a team of costed_team_
  std::size_t costed_team_ = 0;            // 0: none measured
};

}  // namespace kessler::grid
