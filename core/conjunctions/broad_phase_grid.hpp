// Broad phase: a grid of swept boxes, rebuilt every step in O(N), that yields every pair of objects
// which can come within its threshold during the step, and few others. Why it is built this way:
// core/conjunctions/README.md. One file per phase: grid_boxes, grid_cells, grid_sort, grid_balance,
// grid_walk (.cpp, with the shared declarations in grid_boxes/cells/balance.hpp).
#pragma once

#include <atomic>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

#include "core/conjunctions/encounter.hpp"
#include "core/conjunctions/grid_balance.hpp"
#include "core/conjunctions/grid_cells.hpp"
#include "core/conjunctions/hermite_hull.hpp"
#include "core/conjunctions/step_chord.hpp"
#include "core/integration/propagator.hpp"

namespace kessler {

// Below this many objects a step is too small to be worth waking threads for.
inline constexpr std::size_t kParallelMinimumObjects = 1000;

// Each object's share of the threshold [m]: kappa_max r_i, or a fixed share (half the screening distance)
// when no radii are given. Two objects are candidates when their boxes, each grown by its share, overlap.
struct ThresholdShare {
  const double* radius_m = nullptr;
  double kappa = 0.0;
  double fixed_m = 0.0;
  double operator()(std::size_t i) const { return radius_m != nullptr ? kappa * radius_m[i] : fixed_m; }
};

// Two population indices of a candidate pair.
struct CandidatePair {
  std::uint32_t i, j;
};

// How a grid shares out its work, never which pairs it finds.
struct GridSettings {
  // Regions of space: 0 gives one per thread, up to BroadPhaseGrid::kMaxRegions. Benchmarks set 2 on one
  // thread to time the work that a team's regions add to the passes over objects (borders, ghosts),
  // apart from what crosses between cores.
  std::size_t regions = 0;
};

class BroadPhaseGrid {
 public:
  explicit BroadPhaseGrid(const GridSettings& settings = {}) : settings_(settings) {}

  // The escape speed at the Earth's surface [m/s]: no bound orbit above the surface is faster.
  static constexpr double kMaxOrbitalSpeed_m_s = 11190.0;
  // An upper bound of the grid cutoff for any population in a step of dt_s whose largest threshold
  // share per object is max_share_m.
  static double cutoff_bound_m(double dt_s, double max_share_m) {
    return 5.0 / 3.0 * kMaxOrbitalSpeed_m_s * dt_s + 2.0 * max_share_m;
  }

  // Sizes the scratch for n objects and teams of up to `threads` threads (outside a parallel region).
  void prepare(std::size_t n, int threads);
  // The separation rule (Population::separation_group, per object): two objects of the same non-zero
  // group are never a candidate pair. Checked only on the pairs the filters keep, so a young breakup's
  // cloud costs box tests but no memory. Null (the default): no groups.
  void set_separation_groups(const std::uint32_t* groups) { groups_ = groups; }
  // Regions of space, one per thread: the x axis cut into slabs of whole cell columns, each slab's cells
  // hashed into its own range of 2^region_bits buckets (so into its own partitions, sorted and first
  // walked by its thread).
  static constexpr std::size_t kMaxRegions = grid::kMaxRegions;
  // The regions of space of the last prepare().
  std::size_t regions() const { return regions_; }
  // Sort and walk only part `part` of `parts` (the MPI ranks of core/distributed/): the grid gets
  // `parts` times the team's regions (at most kMaxRegions), and this part scatters, sorts and walks the
  // partitions of regions [G part / parts, G (part + 1) / parts) of the G regions only, where every part
  // lays out the same slots (boxes, keys and counts cover the whole population). With more parts than
  // regions, the parts whose share falls in one region each sort all of it and walk their share of its
  // slots. The parts' layouts stay alike only if the cell guesses do: the coarsening follows the
  // occupied cells of all parts (set_all_parts_occupied), or stays where it is. Default: part 0 of 1.
  void set_share(std::size_t part, std::size_t parts) {
    share_part_ = part;
    share_parts_ = parts;
  }
  std::size_t share_part() const { return share_part_; }
  std::size_t share_parts() const { return share_parts_; }
  // The occupied cells of the partitions this grid sorted in its last build (0 on all but the first of
  // the parts that sort one region); and, from a shared grid's caller, their sum over all parts for that
  // build, which the next build's coarsening follows.
  std::size_t sorted_occupied_cells() const;
  void set_all_parts_occupied(std::size_t cells) {
    all_parts_occupied_ = cells;
    all_parts_occupied_known_ = true;
  }
  // Builds the boxes and the grid for one step. Called by every thread of the current team, inside a
  // parallel region, after prepare(); it returns when the thread's own share of the sort is done: the
  // slots of thread u's run may be walked once slots_sorted(u, team) says so (each region is sorted on
  // its own, and every row a slot looks up lies in the slot's region). Objects whose motion spans more
  // than max_motion_m along an axis (or is not finite) are oversized: kept out of the grid, and tested
  // against every object (collect_oversized_pairs). Phases are timed on step.timeline, if any.
  void build_in_team(const StepEnds& step, NarrowPhase motion, const ThresholdShare& share,
                     double max_motion_m, bool with_hulls = false);
  // The same with a team of its own (call outside any parallel region).
  void build(const StepEnds& step, NarrowPhase motion, const ThresholdShare& share, double max_motion_m,
             bool with_hulls = false);

  // Number of slots (objects in bucket order, and the ghosts of boxes at the regions' borders); pairs are
  // enumerated per slot range so threads can split the work.
  std::size_t slot_count() const { return slots_in_grid_; }
  // The slots that thread t of a team of `threads` sorted (its region's, when the team is the size the
  // grid was prepared for): walking them first, a thread reads what its own core wrote.
  std::pair<std::size_t, std::size_t> sorted_slots(std::size_t t, std::size_t threads) const;
  // Whether every region that thread t's run of slots lies in is sorted (false only while the build's
  // team is still sorting).
  bool slots_sorted(std::size_t t, std::size_t threads) const;
  // Appends each candidate pair (boxes overlap, and the chord filter keeps it) whose first member is in
  // slots [slot_begin, slot_end).
  void collect_pairs(std::size_t slot_begin, std::size_t slot_end, std::vector<CandidatePair>& out) const;
  // Seconds thread t spent sorting in the last build.
  double last_sort_s(std::size_t t) const { return thread_sort_s_[t]; }
  // After a scan whose team had a thread per region (else ignored, as is a scan missing a region's
  // cost): each region's cost [s], its sort and every thread's walk of its slots. The next builds'
  // borders give each region a share of the objects inverse to its cost per slot (grid_balance.hpp).
  void record_region_costs(const double* seconds, std::size_t team);
  // Thread t's chunk of the n objects for the passes over objects (boxes, keys, counts, scatter): the
  // propagator's, moved by the threads' measured costs in those passes (grid_balance.hpp, PassBalance).
  ThreadChunk pass_chunk(const ChunkLayout* layout, std::size_t n, std::size_t t, std::size_t team) const {
    return pass_balance_.chunk(layout, n, t, team);
  }
  // Records the costs of the passes over objects from this grid's last build (after a scan whose team
  // was the one asked for).
  void record_pass_costs(std::size_t team) { pass_balance_.record(team); }
  // An object's hull (by population index) as of the last build with_hulls (Hermite motion only).
  const HermiteHull& hull(std::size_t i) const { return hull_[i]; }

  // The oversized objects: pairs of oversized object number [begin, end) with every other object
  // (each pair once).
  std::size_t oversized_count() const { return oversized_.size(); }
  void collect_oversized_pairs(std::size_t begin, std::size_t end, std::vector<CandidatePair>& out) const;

  // The last build's cell edges: along y and z, and along x (the cell columns), which is narrower
  // only where several regions need columns enough to share out.
  double cell_size_m() const { return cell_size_m_; }
  double column_width_m() const { return column_width_m_; }
  // Builds so far, and those whose guessed cell (the last step's) was too small, so keys were computed
  // twice.
  std::size_t builds() const { return builds_; }
  std::size_t rekeyed_builds() const { return rekeyed_builds_; }
  // Whether the last build laid its cells out in spatial order (else it hashed the rows).
  bool cells_in_order() const { return cell_order_.in_order(); }

 private:
  // Tests feed the work balancing costs of their own (tests/conjunctions/broad_phase_grid_test.cpp).
  friend struct GridBalanceProbe;

  // One thread's part of the build in progress: what build_in_team's phases share.
  struct ThreadBuild {
    const StepEnds* step;
    std::size_t t, threads;
    std::size_t begin, end;  // its chunk of objects (pass_chunk)
    // The last build's cell edges (along y and z, and the columns' along x) and extent: this build's
    // guess, read by every thread before any may change them.
    double guess_cell_m, guess_column_m, extent_m;
    std::size_t slot_capacity;  // read before the first barrier: another thread may grow it later
    std::uint32_t* counts;      // its coarse counts per partition
    // The regions' borders along x and the cell columns they fall on, each region's share of the
    // objects, and the bins of this build's histogram of lower x corners (RegionBalance).
    grid::RegionMap map;
    double borders_m[kMaxRegions - 1];
    double shares[kMaxRegions];
    double bin_origin_m, bin_width_m;
  };

  // The walk's box hits waiting for the chord filter and the cell-key check: slot k (self) with slot
  // m (other), whose cell key must lie in [key_lo, key_lo + span]. The walk appends whole groups of
  // lanes without branching on each hit (with AVX-512, only those that pass its float filter:
  // pair_with_slots), and filter_hits then runs the double filter on many hits at once, in vector
  // lanes (one hit's filter alone is a long chain of dependent scalar operations). How the batch is
  // filled never changes what it holds, nor its order.
  static constexpr std::size_t kLanes = 16;  // box tests at once in the walk
  struct HitBatch {
    static constexpr std::size_t kCapacity = 256;
    std::size_t count = 0;
    // kLanes entries beyond the capacity: the walk stores a whole group of lanes past the last hit.
    alignas(64) std::uint32_t self[kCapacity + kLanes];
    alignas(64) std::uint32_t other[kCapacity + kLanes];
    alignas(64) std::uint32_t span[kCapacity + kLanes];
    alignas(64) std::uint64_t key_lo[kCapacity + kLanes];
    bool nearly_full() const { return count > kCapacity - kLanes; }
    // The walk's box-hit rate so far in this call of collect_pairs (halved now and then, so it
    // follows the region): groups of lanes tested, and the box hits they gave.
    std::size_t groups_tested = 0, hits_found = 0;
    void record(std::size_t groups, std::size_t hits) {
      groups_tested += groups;
      hits_found += hits;
      if (groups_tested >= 4096) {
        groups_tested /= 2;
        hits_found /= 2;
      }
    }
    // More than one box hit per 4 groups: then filtering every group costs less than the branches'
    // misses.
    bool dense() const { return 4 * hits_found > groups_tested; }
  };

  // One object's grown box (rounded outwards to floats), cell key, bucket, population index and chord
  // word: 48 bytes, and the whole record the sort moves, so sorting never reads another thread's boxes at
  // random.
  struct GridBox {
    float lo[3], hi[3];
    std::uint32_t crosses;  // crossing bits (grid_cells.hpp)
    std::uint32_t index;
    std::uint64_t key;
    std::uint32_t chord;   // chord_word
    std::uint32_t bucket;  // its cell's (a ghost's: ghost_bucket), kept for the scatter and the sort
  };
  static_assert(sizeof(GridBox) == 48);
  // The counting sort's coarse partitions (top bits of the bucket): at most this many.
  static constexpr std::size_t kMaxPartitions = 256;

  // A slot's word for the chord filter (step_chord.hpp): its reach [m] as a float rounded up to a
  // multiple of 8 in the last place, whose 3 freed bits hold the chord's direction bits (bit set: the
  // box's lower corner stands for the chord's start on that axis, and the upper one for its end). One
  // array, so a hit costs one line beyond the boxes the walk has just read.
  static std::uint32_t chord_word(float reach_m, std::uint32_t ends) {
    return ((std::bit_cast<std::uint32_t>(reach_m) + 7u) & ~7u) | ends;  // >= reach_m (>= 0, finite)
  }
  static float chord_word_reach_m(std::uint32_t word) { return std::bit_cast<float>(word); }
  // The bucket of a ghost marked in a key-pass bucket (grid::kGhostRegionShift).
  std::uint32_t ghost_bucket(std::uint32_t key_pass_bucket) const {
    return (((key_pass_bucket >> grid::kGhostRegionShift) - 1) << region_bits_) |
           (key_pass_bucket & region_mask_);
  }
  // Thread t's run of partitions [first, last) in a team of `threads`, within this part's partitions
  // (set_share): contiguous, in order (it sorts them, and walks their slots first).
  std::pair<std::size_t, std::size_t> partition_run(std::size_t t, std::size_t threads) const {
    const auto [first, last] = shared_partitions();
    return {first + (last - first) * t / threads, first + (last - first) * (t + 1) / threads};
  }
  // This part's share (set_share): regions [first_region, last_region), of whose slots it walks share
  // `sub` of `subs` (more parts than regions: the parts p with G p / parts == the region share it).
  struct RegionShare {
    std::size_t first_region, last_region, sub, subs;
  };
  RegionShare region_share() const {
    const std::size_t g = regions_, part = share_part_, parts = share_parts_;
    if (parts <= g) return {g * part / parts, g * (part + 1) / parts, 0, 1};
    const std::size_t region = g * part / parts;
    const std::size_t first_part = (region * parts + g - 1) / g,
                      end_part = ((region + 1) * parts + g - 1) / g;
    return {region, region + 1, part - first_part, end_part - first_part};
  }
  // The partitions this part sorts: those of its regions (all, unshared).
  std::pair<std::size_t, std::size_t> shared_partitions() const {
    const std::size_t per_region = partitions_ / regions_;
    const RegionShare share = region_share();
    return {per_region * share.first_region, per_region * share.last_region};
  }
  // The region of partition p (each region holds 2^(region_bits_ - fine_bits_) partitions).
  std::size_t region_of_partition(std::size_t p) const { return p >> (region_bits_ - fine_bits_); }
  void ensure_slot_capacity(std::size_t slots);

  // The build's phases (build_in_team), each run by every thread of the team.
  ThreadBuild start_build(const StepEnds& step, std::size_t t, std::size_t threads);
  void before_barrier(std::size_t threads);  // thread 0
  void finish_layout(const ThreadBuild& b, double cell_m, double column_m, double largest_edge_m, bool fits,
                     std::uint32_t total_slots);  // thread 0, after the layout
  // Boxes (grid_boxes.cpp): the grown boxes and chord data of the thread's chunk; then the oversized
  // objects, the samples for the next build's extent and borders, and the largest edge of the others;
  // the hulls.
  void grow_chunk_boxes(const ThreadBuild& b, NarrowPhase motion, const ThresholdShare& share,
                        double max_motion_m);
  double flag_chunk_boxes(const ThreadBuild& b);
  void write_chunk_hulls(const ThreadBuild& b, const ThresholdShare& share);
  // Cells (grid_cells.cpp): keys, buckets and crossing bits of the chunk, and its coarse counts, for cells
  // `column_m` wide along x and `cell_m` along y and z.
  void key_chunk(ThreadBuild& b, double column_m, double cell_m);
  template <bool kInOrder>
  void key_boxes(double inverse_column_m, double inverse_cell_m, const grid::CellOrder& order,
                 std::size_t begin, std::size_t end);
  // With several regions, after key_boxes: each bucket's region, and a ghosted box's mark
  // (grid::kGhostRegionShift). A loop of its own: inside the key loop this work left too few vector
  // registers, and it spilled.
  // kBorders: the borders between regions it need look at.
  template <std::size_t kBorders>
  void add_regions(const grid::RegionMap& regions, std::size_t begin, std::size_t end);
  // The cell order for cells `column` wide along x and `cell` along y and z, when the population's
  // lower corners span about `extent_m` on each axis.
  grid::CellOrder cell_order(double extent_m, double column_m, double cell_m,
                             const grid::RegionMap& regions) const;
  void update_coarsening(std::size_t threads);  // thread 0, before the barrier: from the last build's sort
  void sample_extent(const ThreadBuild& b);
  void update_extent(std::size_t threads);  // thread 0: the next build's extent from the samples
  void guess_next_cell(double cell_m, double column_m, double largest_edge_m, bool fits, double bin_width_m);
  // Sort (grid_sort.cpp): the chunk's coarse counts (after its keys) and its coarse scatter into its
  // part of scratch_, the slot layout (each partition's first slot), and the sort of the thread's
  // partitions.
  void count_chunk(const ThreadBuild& b);
  void scatter_chunk(const ThreadBuild& b);
  std::uint32_t lay_out_partitions(const ThreadBuild& b);
  void sort_partitions(const ThreadBuild& b);
  void sort_partition(const ThreadBuild& b, std::size_t p);
  // Walk (grid_walk.cpp). collect_pairs on slots of the one region starting at bucket `region` (ghosts
  // included: every neighbour row a slot looks up is in its own region).
  template <bool kInOrder>
  void collect_pairs_in(std::size_t slot_begin, std::size_t slot_end, std::size_t region, HitBatch& hits,
                        std::vector<CandidatePair>& out) const;
  // Pairs of slot k with the slots of buckets [first, first + count) of the region starting at bucket
  // `region` (wrapping at its end; in the first bucket only from slot `from` on), whose cell keys are in
  // [key_lo, key_lo + span].
  void pair_with_buckets(std::size_t k, std::size_t region, std::size_t first, std::size_t count,
                         std::size_t from, std::uint64_t key_lo, std::uint64_t span, HitBatch& hits,
                         std::vector<CandidatePair>& out) const;
  // Pairs of slot k with the slots [first, last) whose cell keys are in [key_lo, key_lo + span]: the
  // box hits go to `hits`, which is filtered into `out` whenever it fills.
  void pair_with_slots(std::size_t k, std::size_t first, std::size_t last, std::uint64_t key_lo,
                       std::uint64_t span, HitBatch& hits, std::vector<CandidatePair>& out) const;
  // Appends each hit of the batch that the chord filter keeps and whose key is in range to `out` (in
  // the batch's order), and empties the batch.
  void filter_hits(HitBatch& hits, std::vector<CandidatePair>& out) const;
  // Whether any of the buckets [first, first + count) of the region starting at bucket `region`
  // (wrapping at its end) holds a slot.
  bool any_occupied(std::size_t region, std::size_t first, std::size_t count) const {
    for (std::size_t d = 0; d < count; ++d) {
      const std::size_t b = region | ((first + d) & region_mask_);
      if ((occupied_[b >> 6] >> (b & 63)) & 1u) return true;
    }
    return false;
  }

  GridSettings settings_;
  std::size_t share_part_ = 0, share_parts_ = 1;  // set_share
  std::size_t all_parts_occupied_ = 0;            // set_all_parts_occupied, for the last build
  bool all_parts_occupied_known_ = false;
  // Cells: the last build's edges and order, and what the next build starts from. The candidates never
  // depend on the cell edges (only on the boxes), so carrying them from step to step changes no result,
  // and saves a pass when they fit.
  double cell_size_m_ = 0.0, column_width_m_ = 0.0;
  grid::CellOrder cell_order_;
  double next_cell_m_ = 0.0, next_column_m_ = 0.0;
  std::size_t builds_ = 0, rekeyed_builds_ = 0;
  // The cell edge over the largest box edge (>= 1: coarser cells where the population is sparse).
  double coarsening_ = 1.0;
  // The edge of the cube centred on the origin that holds the population's lower corners [m] but a few
  // far out, from the last build: each thread's histogram of max |corner coordinate| on every
  // kExtentStride-th object. (Only the cell order depends on it, never a result.)
  static constexpr std::size_t kExtentBins = 64, kExtentStride = 16;
  static constexpr double kDefaultExtent_m = 2.0e7;
  double next_extent_m_ = kDefaultExtent_m;
  std::vector<std::uint32_t> thread_extent_hist_;
  // Buckets and partitions.
  std::size_t regions_ = 1, region_mask_ = 0, partitions_ = 1;
  int region_bits_ = 0, fine_bits_ = 0;
  std::size_t prepared_threads_ = 0;
  // Work balancing (grid_balance.hpp).
  grid::RegionBalance region_balance_;
  grid::PassBalance pass_balance_;
  // The box and key passes' output per object (population index), arrays so that the passes vectorise:
  // the grown box rounded to floats, the chord filter's reach and direction bits, the oversized flag;
  // the cell key, bucket and crossing bits (the scatter assembles them into GridBox records).
  std::vector<float> box_lo_[3], box_hi_[3], box_reach_;
  std::vector<std::uint32_t> box_flags_;
  std::vector<std::uint64_t> box_key_;
  std::vector<std::uint32_t> box_bucket_;
  std::vector<std::uint8_t> box_crosses_;
  std::vector<HermiteHull> hull_;  // per object, with Hermite motion
  std::vector<char> oversized_flag_;
  std::vector<std::uint32_t> oversized_;  // population indices, ascending
  std::vector<std::vector<std::uint32_t>> thread_oversized_;
  std::vector<double> thread_edge_;  // per thread: the largest box edge of its chunk
  // Slots (bucket order): the boxes axis by axis (lower x, y, z, upper x, y, z), each padded by kLanes
  // entries so the walk's last group of lanes reads inside the array; keys; crossing bits; population
  // indices; chord words.
  std::size_t slots_in_grid_ = 0;  // objects in the grid plus ghosts
  std::size_t slot_capacity_ = 0;  // slots the arrays have room for (ghosts make them more than objects)
  std::vector<float> slot_box_[6];
  std::vector<std::uint64_t> slot_key_;
  std::vector<std::uint8_t> slot_crosses_;  // GridBox::crosses
  std::vector<std::uint32_t> slot_index_;
  const std::uint32_t* groups_ = nullptr;  // set_separation_groups
  // Appends the pair (population indices) unless the separation rule keeps it out.
  void keep_pair(std::vector<CandidatePair>& out, std::uint32_t i, std::uint32_t j) const {
    if (groups_ != nullptr && groups_[i] != 0 && groups_[i] == groups_[j]) return;
    out.push_back(CandidatePair{i, j});
  }
  std::vector<std::uint32_t> slot_chord_;    // GridBox::chord
  std::vector<std::uint32_t> bucket_start_;  // size buckets + 1
  std::vector<std::uint64_t> occupied_;      // one bit per bucket
  // Counting-sort scratch, two records per object (a box and its ghost at most): each thread's boxes
  // grouped by coarse partition in [2 begin, 2 end) of its chunk [begin, end), so the scatter writes no
  // cache line another thread writes and needs no other thread's counts (it runs before the barrier).
  std::vector<GridBox> scratch_;
  // Per thread and partition: its count and where its group starts in scratch_.
  std::vector<std::uint32_t> coarse_count_, group_start_, partition_start_;
  // Per thread: the sort's bucket counts, then cursors, for the partition at hand (kept out of
  // bucket_start_, whose partition edges the walks of other regions read meanwhile).
  std::vector<std::vector<std::uint32_t>> thread_bucket_cursor_;
  // Per thread: the occupied buckets of the partitions it sorted in the last build (of a team of
  // occupancy_team_), for the coarsening.
  std::vector<std::uint32_t> thread_occupied_;
  std::size_t occupancy_team_ = 0;
  std::vector<double> thread_sort_s_;  // per thread: the last build's sort [s]
  // A counter on its own cache line, released by the threads that add to it and acquired by the walkers.
  struct alignas(64) LineCounter {
    std::atomic<std::uint32_t> count{0};
  };
  // Per region: its partitions sorted so far in this build.
  std::unique_ptr<LineCounter[]> region_progress_ = std::make_unique<LineCounter[]>(kMaxRegions);
  // After the barrier, each thread counts itself in here once it has set its partitions' starts (which
  // the walks of the run below read as their end), and thread 0 once more when it has set the cells,
  // slot count and oversized list: no walk begins before the team's threads + 1 (slots_sorted).
  std::unique_ptr<LineCounter> layout_ready_ = std::make_unique<LineCounter>();
};

}  // namespace kessler
