// The grid's build, phase by phase (each phase in its own file: grid_boxes.cpp, grid_cells.cpp,
// grid_sort.cpp, grid_balance.cpp), and the sizing of its scratch.
//
// The same pragma as the phases' files (grid_boxes.cpp): no value changes.
#pragma GCC optimize("no-trapping-math")

#include "core/conjunctions/broad_phase_grid.hpp"

#include <omp.h>

#include <algorithm>
#include <stdexcept>
#include <string>

#include "core/parallel/team_timeline.hpp"
#include "core/parallel/thread_chunks.hpp"

namespace kessler {
namespace {

// Whether boxes no larger than edge_m fit the guessed cell (1e-9: rounding of the keys).
bool fits_guess(double guess_cell_m, double guess_column_m, double edge_m) {
  return guess_cell_m > 0.0 && edge_m * (1.0 + 1e-9) <= std::min(guess_cell_m, guess_column_m);
}

}  // namespace

void BroadPhaseGrid::prepare(std::size_t n, int threads) {
  box_key_.resize(n);
  box_bucket_.resize(n);
  box_crosses_.resize(n);
  for (auto& axis : box_lo_) axis.resize(n);
  for (auto& axis : box_hi_) axis.resize(n);
  box_reach_.resize(n);
  box_flags_.resize(n);
  hull_.resize(n);
  oversized_flag_.resize(n);
  scratch_.resize(2 * n);
  ensure_slot_capacity(n);
  // One region per thread (at most kMaxRegions), per thread of each part when shared (set_share). At least 2
  // buckets per object in all, a power of two per region: occupied cells hold 4-8 objects where the
  // coarsening can reach that (load ~1/16), and one object at worst (load <= 1/2); the occupancy bitmap makes
  // empty buckets cheap. Each step the sort clears, counts and sums the whole table, so more buckets per
  // object cost more than they save. Up to kMaxPartitions coarse partitions for the sort, each of at least 64
  // buckets.
  const std::size_t team = static_cast<std::size_t>(std::max(threads, 1));
  regions_ = std::min(settings_.regions > 0 ? settings_.regions : team * share_parts_, kMaxRegions);
  std::size_t region_buckets = 64;
  int bits = 6;
  while (regions_ * region_buckets < 2 * n) {
    region_buckets *= 2;
    ++bits;
  }
  region_bits_ = bits;
  region_mask_ = region_buckets - 1;
  const std::size_t buckets = regions_ * region_buckets;
  if (buckets > std::size_t{grid::kBucketMask} + 1)
    throw std::length_error("conjunction grid: " + std::to_string(n) +
                            " objects are more than its buckets can key");
  // Each thread scatters its chunk into every partition: with fewer than ~32 objects per thread and
  // partition, threads would write the same cache lines. So partitions <= n / (32 threads).
  int region_partition_bits = 0;
  while (region_partition_bits < bits - 6 && (regions_ << (region_partition_bits + 1)) <= kMaxPartitions &&
         (regions_ << (region_partition_bits + 1)) * 32 * team <= n)
    ++region_partition_bits;
  partitions_ = regions_ << region_partition_bits;
  fine_bits_ = bits - region_partition_bits;
  const std::size_t partitions = partitions_;
  bucket_start_.resize(buckets + 1);
  occupied_.resize(buckets / 64);
  coarse_count_.resize(team * partitions);
  group_start_.resize(team * partitions);
  thread_oversized_.resize(team);
  thread_edge_.resize(team);
  thread_occupied_.resize(team);
  thread_sort_s_.resize(team);
  pass_balance_.prepare(team);
  region_balance_.prepare(regions_, team);
  occupancy_team_ = std::min(occupancy_team_, team);
  partition_start_.resize(partitions);
  thread_bucket_cursor_.resize(team);
  for (auto& cursor : thread_bucket_cursor_) cursor.resize(std::size_t{1} << fine_bits_);
  thread_extent_hist_.resize(team * kExtentBins);
  prepared_threads_ = team;
}

void BroadPhaseGrid::ensure_slot_capacity(std::size_t slots) {
  if (slots <= slot_capacity_) return;
  // Room for ghosts beyond the objects (about 1 % of them with 2 threads, more with more regions), so
  // that the arrays seldom grow again.
  slot_capacity_ = slots + slots / 8;
  for (auto& axis : slot_box_) axis.resize(slot_capacity_ + kLanes);
  slot_chord_.resize(slot_capacity_ + kLanes);
  slot_key_.resize(slot_capacity_);
  slot_crosses_.resize(slot_capacity_);
  slot_index_.resize(slot_capacity_);
}

void BroadPhaseGrid::build(const StepEnds& step, NarrowPhase motion, const ThresholdShare& share,
                           double max_motion_m, bool with_hulls) {
  const std::size_t n = step.start->size();
  const int threads = n >= kParallelMinimumObjects ? omp_get_max_threads() : 1;
  prepare(n, threads);
  TeamTimeline* const timeline = step.timeline;
  if (timeline) timeline->region_start(static_cast<std::size_t>(threads));
#pragma omp parallel num_threads(threads)
  {
    if (timeline) timeline->enter(static_cast<std::size_t>(omp_get_thread_num()));
    build_in_team(step, motion, share, max_motion_m, with_hulls);
  }
  if (timeline) timeline->region_end();
}

// One barrier, after the boxes, keys and the scatter of each thread's chunk into coarse partitions (which
// needs no other thread's counts), then each partition's sort by fine bucket, with no barrier after it (a
// region's walk waits for that region's sort alone: slots_sorted), and no serial section: every thread
// computes the partition layout itself from all threads' counts.
void BroadPhaseGrid::build_in_team(const StepEnds& step, NarrowPhase motion, const ThresholdShare& share,
                                   double max_motion_m, bool with_hulls) {
  const std::size_t threads = static_cast<std::size_t>(omp_get_num_threads());
  const std::size_t t = static_cast<std::size_t>(omp_get_thread_num());
  if (threads > prepared_threads_) throw std::logic_error("BroadPhaseGrid: team larger than prepared");
  TeamTimeline* const timeline = step.timeline;
  ThreadBuild b = start_build(step, t, threads);
  const double pass_start_s = omp_get_wtime();

  // The passes over this thread's chunk: boxes, then (with the guessed cell) keys, counts and scatter.
  grow_chunk_boxes(b, motion, share, max_motion_m);
  if (timeline) timeline->mark(t, kDetGrow);
  const double largest_edge = flag_chunk_boxes(b);
  sample_extent(b);
  if (regions_ > 1)
    region_balance_.sample(t, box_lo_[0].data(), oversized_flag_.data(), b.begin, b.end, b.bin_origin_m,
                           b.bin_width_m);
  if (motion == NarrowPhase::kHermite && with_hulls) write_chunk_hulls(b, share);
  thread_edge_[t] = largest_edge;
  if (timeline) timeline->mark(t, kDetEdges);
  // A chunk that does not fit the guess means that every thread keys again after the barrier.
  const bool own_fits = fits_guess(b.guess_cell_m, b.guess_column_m, largest_edge);
  if (own_fits) {
    key_chunk(b, b.guess_column_m, b.guess_cell_m);
    count_chunk(b);
  }
  if (timeline) timeline->mark(t, kDetKeys);
  if (own_fits) scatter_chunk(b);
  if (timeline) timeline->mark(t, kDetScatter);
  if (t == 0) before_barrier(threads);
  double pass_s = omp_get_wtime() - pass_start_s;
#pragma omp barrier
  if (timeline) timeline->mark(t, kDetWait);

  // Every thread takes the same maximum over the chunks (exact: no order dependence).
  double largest = 0.0;
  for (std::size_t u = 0; u < threads; ++u) largest = std::max(largest, thread_edge_[u]);
  double cell = b.guess_cell_m, column = b.guess_column_m;
  const bool fits = fits_guess(b.guess_cell_m, b.guess_column_m, largest);
  if (!fits) {
    // The guess is too small (or there is none): key and scatter again with a cell of this step's
    // largest edge, and the borders from this build's histogram (only the first build needs it).
    const double rekey_start_s = omp_get_wtime();
    cell = column = grid::fitting_cell_m(largest);
    if (regions_ > 1)
      region_balance_.borders_from_this(regions_, threads, b.shares, b.bin_origin_m, b.bin_width_m,
                                        b.borders_m);
    key_chunk(b, column, cell);
    count_chunk(b);
    scatter_chunk(b);
    pass_s += omp_get_wtime() - rekey_start_s;
#pragma omp barrier
  }
  pass_balance_.measured(t, pass_s, b.end - b.begin);
  if (regions_ > 1) region_balance_.sum_slice(t, threads);  // every thread has read the last one

  const std::uint32_t total_slots = lay_out_partitions(b);
  if (total_slots > b.slot_capacity) {
    // More ghosts than the arrays have room for (every thread sees the same total and capacity, so all
    // of them come here): nobody reads or writes the arrays until the sort below.
#pragma omp single
    ensure_slot_capacity(total_slots);
  }
  if (t == 0) finish_layout(b, cell, column, largest, fits, total_slots);
  if (timeline) timeline->mark(t, kDetLayout);
  const double sort_start_s = omp_get_wtime();
  sort_partitions(b);
  thread_sort_s_[t] = omp_get_wtime() - sort_start_s;
  if (timeline) timeline->mark(t, kDetSort);
}

BroadPhaseGrid::ThreadBuild BroadPhaseGrid::start_build(const StepEnds& step, std::size_t t,
                                                        std::size_t threads) {
  ThreadBuild b;
  b.step = &step;
  b.t = t;
  b.threads = threads;
  // Each thread owns the chunk of objects whose end states the propagator wrote on this core
  // (thread_chunks.hpp), so the first pass reads what this core holds; its borders moved by the
  // threads' measured costs (pass_chunk).
  const auto [begin, end] = pass_chunk(step.chunks, step.start->size(), t, threads);
  b.begin = begin;
  b.end = end;
  b.guess_cell_m = next_cell_m_;
  b.guess_column_m = next_column_m_;
  b.extent_m = next_extent_m_;
  b.slot_capacity = slot_capacity_;
  b.counts = &coarse_count_[t * partitions_];
  // The regions' borders along x: from the last build's histogram (a build that keys again after the
  // barrier takes them from its own: the first one has no other). Every thread computes the same
  // borders and cell columns itself, so no thread waits for them.
  b.map.region_bits = region_bits_;
  std::fill(std::begin(b.map.first_column), std::end(b.map.first_column), ~std::uint32_t{0});
  b.bin_origin_m = grid::RegionBalance::kDefaultBinOrigin_m;
  b.bin_width_m = grid::RegionBalance::kDefaultBinWidth_m;
  region_balance_.shares(regions_, b.shares);
  if (regions_ > 1)
    region_balance_.borders_from_last(regions_, b.shares, b.borders_m, b.bin_origin_m, b.bin_width_m);
  return b;
}

void BroadPhaseGrid::before_barrier(std::size_t threads) {
  // What depends on the last build alone (the sorts after the barrier change both).
  update_coarsening(threads);
  for (std::size_t r = 0; r < regions_; ++r) region_progress_[r].count.store(0, std::memory_order_relaxed);
  layout_ready_->count.store(0, std::memory_order_relaxed);
}

void BroadPhaseGrid::finish_layout(const ThreadBuild& b, double cell_m, double column_m,
                                   double largest_edge_m, bool fits, std::uint32_t total_slots) {
  cell_size_m_ = cell_m;
  column_width_m_ = column_m;
  cell_order_ = b.map.order;  // the final keys'
  update_extent(b.threads);
  ++builds_;
  if (!fits) ++rekeyed_builds_;
  slots_in_grid_ = total_slots;
  oversized_.clear();  // in population order (the chunks are in order)
  for (std::size_t u = 0; u < b.threads; ++u)
    oversized_.insert(oversized_.end(), thread_oversized_[u].begin(), thread_oversized_[u].end());
  guess_next_cell(cell_m, column_m, largest_edge_m, fits, b.bin_width_m);
  if (regions_ > 1) region_balance_.keep_bins(b.bin_origin_m, b.bin_width_m);
  // The walks may begin (slots_sorted): the cells, slot count and oversized list are set.
  layout_ready_->count.fetch_add(1, std::memory_order_release);
}

std::pair<std::size_t, std::size_t> BroadPhaseGrid::sorted_slots(std::size_t t, std::size_t threads) const {
  auto slot_of = [&](std::size_t p) -> std::size_t {
    return p < partitions_ ? partition_start_[p] : slots_in_grid_;
  };
  const auto [first, last] = partition_run(t, threads);
  const RegionShare share = region_share();
  if (share.subs == 1) return {slot_of(first), slot_of(last)};
  // One region sorted by several parts: each walks its share of the region's slots.
  const auto [region_first, region_last] = shared_partitions();
  const std::size_t begin = slot_of(region_first), slots = slot_of(region_last) - begin;
  const std::size_t cut_first = begin + slots * share.sub / share.subs;
  const std::size_t cut_last = begin + slots * (share.sub + 1) / share.subs;
  const std::size_t lo = std::max(slot_of(first), cut_first), hi = std::min(slot_of(last), cut_last);
  return {lo, std::max(lo, hi)};
}

bool BroadPhaseGrid::slots_sorted(std::size_t t, std::size_t threads) const {
  if (layout_ready_->count.load(std::memory_order_acquire) != threads + 1) return false;
  const auto [first, last] = partition_run(t, threads);
  if (first >= last) return true;
  const std::uint32_t per_region = 1u << (region_bits_ - fine_bits_);
  for (std::size_t r = region_of_partition(first); r <= region_of_partition(last - 1); ++r)
    if (region_progress_[r].count.load(std::memory_order_acquire) != per_region) return false;
  return true;
}

void BroadPhaseGrid::record_region_costs(const double* seconds, std::size_t team) {
  if (team != regions_ || regions_ < 2) return;  // each thread's run a region: else not one region's
  std::size_t slots[kMaxRegions];
  for (std::size_t r = 0; r < regions_; ++r) {
    const auto [first, last] = sorted_slots(r, team);
    slots[r] = last > first ? last - first : 0;
  }
  region_balance_.record(seconds, slots, regions_);
}

}  // namespace kessler
