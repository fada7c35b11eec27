// Broad phase: a hashed grid of swept boxes, rebuilt every step in O(N), that yields every pair of
// objects which can come within its threshold at any moment of the step, and few others.
//
// Cutoff derivation. Over a step each object stays inside a box known from its end states alone:
//   - Hermite motion is the cubic Bezier curve with control points p0, p0 + dt v0 / 3, p1 - dt v1 / 3,
//     p1, and a Bezier curve lies in the convex hull of its control points, so in their bounding box;
//   - the paper's straight line lies in the box of p0 and p0 + dt v0.
// Each box is grown by the object's share of the threshold, h_i = kappa_max r_i (or half the screening
// distance), plus 1 mm against rounding. Two objects can be within kappa_max (r_i + r_j) (or the
// screening distance) at some instant only if their grown boxes overlap: they would have to be within
// that distance even allowing each to be anywhere in its box at any time.
// The grid's cell edge L is at least the largest edge of any grown box in this step: the largest
// displacement of an object in the step along an axis plus the largest threshold share, i.e. the
// cutoff. (It is guessed from the last step, the keys then computed in the same pass as the boxes with
// no wait for the maximum, and computed again from this step's largest edge plus 0.5 % when the boxes
// do not fit the guess: the candidates depend only on the boxes, never on L. Where the population is
// sparse, L is a multiple of the largest edge, chosen so that occupied cells hold 4-8 objects: see
// kSparseObjectsPerCell; with several regions of space, cells may be narrower along x than along y and
// z, each edge still at least the largest box edge.) If two boxes overlap on an axis, lo_j <= hi_i
// <= lo_i + L and lo_i <= lo_j + L, so their lower corners are within L (that axis's edge) and fall in
// the same or adjacent cells. Every overlapping pair is therefore found by looking at a cell and its 26
// neighbours (13 forward ones plus itself, each unordered pair once), and the exact box-overlap test keeps
// only real candidates. An upper bound of L for any population (validation): a bound orbit above the Earth's
// surface moves at most at the surface escape speed (11.19 km/s), and the Bezier hull spans at most 5/3 of v
// dt, so L <= 5/3 * 11.19 km/s * dt + 2 max h_i.
//
// Objects whose motion spans more than that bound along an axis (non-finite or unbound states: a propagation
// gone wrong, an object falling through the Earth before its burn-up is applied) would blow the cell up and
// make every pair a neighbour. They are kept out of the grid and tested against every object instead
// (O(N) each, in vector lanes), so one bad object costs O(N), not O(N^2). So are objects far out: real
// catalogs hold some at ~10^12 m, where rounding to floats widens a box by ~240 km a side. Kept in the
// grid, the paper catalog's 13 such objects set its cell edge (527 km where its bound orbits need 240)
// and, at 16 threads, left its fullest region of space with 1.67x the mean share of objects (1.28x
// without them). A box reaching beyond 10^9 m on any axis is far out; every grid box then lies inside
// the cube of that half-edge, and an oversized box that misses the cube is tested against the other
// oversized objects alone (the same pairs, without the O(N) scan).
//
// Cells are hashed into a table of >= 2 N buckets: a hash of the cell's (x, y) row plus its z index, so
// the cells along z are consecutive buckets and the 13 forward neighbours are 5 bucket ranges (own cell
// and z + 1; z - 1..z + 1 of four neighbouring rows); an occupancy bitmap (1 bit per bucket)
// skips empty ones. Objects are ordered by bucket with a parallel, stable counting sort, so memory and
// time stay O(N) whatever the domain's size and the result never depends on threads.
// Where the population's cells fit the table, they are laid out in spatial order instead of hashed:
// bucket x P + y R + z (CellOrder), over the cube that holds all but 0.5 % of the lower corners (each
// build samples them for the next; objects beyond alias onto cells inside, which the walk's key check
// drops). The walk then goes plane by plane in x, and the rows it looks up (this plane's and the next)
// were read a plane before, so they are still in the core's cache: at 320,000 objects hashed rows sent
// nearly every row lookup to the last-level cache, and the walk fell from 72 to 53 ns per object-step
// in order (the cost was the latency of those lookups, not the slots' bytes: 16-bit boxes, half the
// bytes, walked slower). The forward rows are then at fixed offsets from the cell's own bucket. Cells
// too fine for the table (P times the columns no larger than a region's buckets) keep hashed rows.
// The build runs inside the caller's parallel region with one barrier, after the boxes, keys and the
// scatter of each thread's chunk into coarse partitions (its own part of the scratch, which needs no
// other thread's counts), then each partition's sort by fine bucket, with no barrier after it (a
// region's walk waits for that region's sort alone, and for every thread's partition starts), and no
// serial section: every thread computes the partition layout itself from all threads' counts. Each thread
// keeps the contiguous chunk of objects whose end states the propagator wrote on the same core
// (thread_chunks.hpp).
//
// Regions of space, one per thread: the x axis is cut into slabs of whole cell columns, and each slab's
// cells hash into its own power-of-two range of buckets, so into partitions that one thread sorts and
// then walks first. A cell's neighbour rows lie in its own column or the next, so nearly all of them
// are in the same region: the walk reads slot lines its own core wrote in the sort, and the next sort
// rewrites lines only its own core read. (With one hash over all buckets, a neighbour row belonged to
// any thread: 2 threads on cores that share no cache spent 1.6x their share of the sort and 1.3x of
// the walk fetching and invalidating each other's lines.) The rows of the next column across a border
// are the other region's: a box of a region's last column that reaches into the next column gets a
// copy (a ghost) sorted into the next region, under its own cell key, and that region walks the ghost's
// next-column rows, on its own lines; the box itself walks only its own column's. (Walked from the
// last column, the border's rows took the other core's bucket-table and slot lines, and its next sort
// took them back: 2 threads far apart sorted 81 ms a thread against 64 for the one whose rows were not
// read, leo-19647's quarter day.) The borders between the slabs give each region a share of the
// objects inverse to its measured cost per slot (record_region_costs: its sort and walks, smoothed over
// scans; equal shares until measured): quantiles of a histogram of the lower x corners of the last
// build's boxes (every 4th object; a first build, which keys after the barrier anyway, takes its own),
// each moved to the nearest column edge; the histogram's bins span the last one's central 99 %, since
// catalogs hold a few objects far out (the paper's, some at 10^12 m). Only the balance between threads
// depends on the borders: the candidates are the same for any borders.
// (Spatial order was first tried in session 3, when the walk read one 64-byte record per slot and
// was bound by its tests: 149.7 vs 145.5 ns per object-step at 320k, equal at 19,647. The walk of
// float lanes that replaced it is bound by its row lookups, where the order pays: see above.)
//
// Exact pruning of the walk: cells along an axis are monotone in the coordinate, so a box whose upper
// corner lies in its lower corner's cell on an axis is below every lower corner of the next cell on
// that axis and cannot overlap a box of that cell. The walk visits the x + 1 rows only for boxes that
// cross into the next x cell, the y + 1 rows only for those crossing in y, and the z + 1 cells only for
// those crossing in z: the same candidate pairs, about half the cells visited.
//
// Boxes are kept in single precision, each corner rounded outwards by 2^-22 of its coordinate (at most
// 1.7 m in LEO, against boxes tens of km wide): still a box that holds the grown one, so every pair
// above stays a candidate, and the walk tests 16 slots at once on six float arrays (24 bytes per visited
// slot). In dense populations each object tests hundreds of slots per step, and this test is most of
// the walk. Keys, crossing bits and the overlap test all use the same float corners, so the argument
// above holds for them exactly.
//
// Each pair whose boxes overlap must also pass the chord filter (step_chord.hpp) to become a candidate:
// in dense populations most such pairs cross the common region at different times, and the filter, on
// the float corners the walk holds plus one word per slot (reach and direction bits), drops them (at
// 320,000 objects, 2.4 box pairs per object and step, 0.1 % kept). With AVX-512 the walk runs a
// single-precision version of the filter, loose enough never to drop a pair the double one keeps, on
// the 16 lanes it has just tested (the boxes are in its registers: only the chord words are loaded);
// where box hits are dense on every group without a branch, where they are sparse only on the groups
// that hit (the rate so far decides). Its few survivors go to a batch on which the double filter runs
// 8 at a time. (Batching every box hit for the double filter, which gathers both slots' data, cost
// 22 ns per object and step at 320,000 objects; the float filter in the walk, about half that.)
//
// With Hermite motion the build can also write each object's hull (hermite_hull.hpp): the single-
// precision Bezier control points on which the narrow phase's cheap filters run first, reading one
// cache line per object instead of twelve state arrays, where candidates are still many per object.
#pragma once

#include <atomic>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

#include "core/conjunctions/encounter.hpp"
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

class BroadPhaseGrid {
 public:
  // The escape speed at the Earth's surface [m/s]: no bound orbit above the surface is faster.
  static constexpr double kMaxOrbitalSpeed_m_s = 11190.0;
  // An upper bound of the grid cutoff for any population in a step of dt_s whose largest threshold
  // share per object is max_share_m.
  static double cutoff_bound_m(double dt_s, double max_share_m) {
    return 5.0 / 3.0 * kMaxOrbitalSpeed_m_s * dt_s + 2.0 * max_share_m;
  }

  // Sizes the scratch for n objects and teams of up to `threads` threads (outside a parallel region).
  void prepare(std::size_t n, int threads);
  // Regions of space, one per thread (see above): the x axis cut into slabs of whole cell columns,
  // each slab's cells hashed into its own range of 2^region_bits buckets (so into its own partitions,
  // sorted and first walked by its thread).
  static constexpr std::size_t kMaxRegions = 16;
  // Regions of space from the next prepare() on: 0 (the default) gives one per thread, up to
  // kMaxRegions. Benchmarks set 2 on one thread to time the work that a team's regions add to the
  // passes over objects (borders, ghosts), apart from what crosses between cores. The pairs are the same.
  void set_regions(std::size_t regions) { requested_regions_ = regions; }
  // The regions of space of the last prepare().
  std::size_t regions() const { return regions_; }
  // Builds the boxes and the grid for one step. Called by every thread of the current team, inside a
  // parallel region, after prepare(); it returns when the thread's own share of the sort is done: the
  // slots of thread u's run may be walked once slots_sorted(u, team) says so (each region is sorted on
  // its own, and every row a slot looks up lies in the slot's region). Objects whose motion spans more
  // than max_motion_m along an axis (or is not finite) are oversized: kept out of the grid (see above).
  void build_in_team(const StepEnds& step, NarrowPhase motion, const ThresholdShare& share,
                     double max_motion_m, bool with_hulls = false);
  // The same with a team of its own (call outside any parallel region).
  void build(const StepEnds& step, NarrowPhase motion, const ThresholdShare& share, double max_motion_m,
             bool with_hulls = false);

  // Number of slots (objects in bucket order, and the ghosts of boxes at the regions' borders); pairs are
  // enumerated per slot range so threads can split the work. Appends each candidate pair (boxes overlap)
  // whose first member is in [slot_begin, slot_end).
  std::size_t slot_count() const { return slots_in_grid_; }
  // The slots that thread t of a team of `threads` sorted (its region's, when the team is the size the
  // grid was prepared for): walking them first, a thread reads what its own core wrote.
  std::pair<std::size_t, std::size_t> sorted_slots(std::size_t t, std::size_t threads) const;
  // Whether every region that thread t's run of slots lies in is sorted (false only while the build's
  // team is still sorting).
  bool slots_sorted(std::size_t t, std::size_t threads) const;
  void collect_pairs(std::size_t slot_begin, std::size_t slot_end, std::vector<CandidatePair>& out) const;
  // Seconds thread t spent sorting in the last build.
  double last_sort_s(std::size_t t) const { return thread_sort_s_[t]; }
  // After a scan whose team had a thread per region (else ignored, as is a scan missing a region's
  // cost): each region's cost [s], its sort and every thread's walk of its slots. The next builds'
  // borders give each region a share of the objects inverse to its cost per slot, smoothed over scans,
  // so that a region whose slots cost more (denser cells, a slower or busier core, the ghosts it holds)
  // gets fewer. Only the balance between threads depends on it, never a result.
  void record_region_costs(const double* seconds, std::size_t team);
  // The passes over objects (boxes, keys, counts, scatter) take each thread's chunk: the propagator's (each
  // core reads the states it wrote), resized so that the threads finish them together: a core slower at them
  // (a busier one, or one whose cache another tenant shares) gets fewer objects. Each chunk is weighted by 1
  // / its thread's cost per object in those passes, recorded after each build (seconds and objects per thread
  // of a team), smoothed over builds, and clamped within 1.5x of the team's mean; the propagator's chunks
  // until measured, and for a team of one. Only which core handles an object depends on it, never a result:
  // the chunks stay contiguous and in order.
  // Thread t's chunk of the n objects: thread_chunk's (the propagator's layout), moved by the recorded costs.
  ThreadChunk pass_chunk(const ChunkLayout* layout, std::size_t n, std::size_t t, std::size_t team) const;
  // Records the costs from this grid's last build (after a scan whose team was the one asked for).
  void record_pass_costs(std::size_t team);
  // The same with the given seconds and objects per thread, in place of the last build's.
  void record_pass_costs(const double* seconds, const std::size_t* objects, std::size_t team);
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
    // misses (the same at 2 or 8, measured at 40,000 and 80,000 objects).
    bool dense() const { return 4 * hits_found > groups_tested; }
  };
  // collect_pairs on slots of the one region starting at bucket `region` (ghosts included: every
  // neighbour row a slot looks up is in its own region).
  template <bool kInOrder>
  void collect_pairs_in(std::size_t slot_begin, std::size_t slot_end, std::size_t region, HitBatch& hits,
                        std::vector<CandidatePair>& out) const;
  // Appends each hit of the batch that the chord filter keeps and whose key is in range to `out` (in
  // the batch's order), and empties the batch.
  void filter_hits(HitBatch& hits, std::vector<CandidatePair>& out) const;
  // How cells are laid out in a region's buckets (bucket_in_region): row_stride 0 hashes the rows;
  // otherwise cell (x, y, z) goes to x plane_stride + y row_stride + z.
  struct CellOrder {
    std::uint64_t plane_stride = 0, row_stride = 0, origin = 0;
    bool in_order() const { return row_stride != 0; }
  };
  struct RegionMap {
    // The first cell column of regions 1, 2, ... (padded with the largest value: never reached).
    std::uint32_t first_column[kMaxRegions - 1];
    int region_bits = 0;
    CellOrder order;
    // The region of cell column `column`: the number of borders at or below it, counted over the first
    // kBorders borders (all of them by default: the unused ones are the largest column, never reached).
    // In the key pass's vector lanes these are compares with constants; a binary search, whose loads
    // depend on the last step, made four gathers of them and cost more.
    template <std::size_t kBorders = kMaxRegions - 1>
    std::uint32_t region_of(std::uint32_t column) const {
      std::uint32_t region = 0;
      for (std::size_t s = 0; s < kBorders; ++s) region += column >= first_column[s] ? 1 : 0;
      return region;
    }
  };
  // Cell keys, buckets within a region and crossing bits (GridBox) of objects [begin, end) from their
  // float boxes, for cells 1 / inverse_column_m wide along x and 1 / inverse_cell_m along y and z: a loop
  // over arrays that vectorises.
  template <bool kInOrder>
  void key_boxes(double inverse_column_m, double inverse_cell_m, const CellOrder& order, std::size_t begin,
                 std::size_t end);
  // With several regions, after key_boxes: each bucket's region, and a ghosted box's mark
  // (kGhostRegionShift). A loop of its own: inside the key loop this work left too few vector registers,
  // and it spilled (2 regions on one thread: 0.5 ns more per object than one region). kBorders: the
  // borders between regions it need look at.
  template <std::size_t kBorders>
  void add_regions(const RegionMap& regions, std::size_t begin, std::size_t end);
  // A cell's bucket is its region's first bucket (region << region_bits) plus bucket_in_region: its place in
  // spatial order, or a hash of its row (x, y), plus its z cell, so the cells of a row along z fall in
  // consecutive buckets of one region (and, sorted by bucket, in consecutive slots): the three z
  // neighbours of a cell are one contiguous range (wrapping inside the region), usually on one cache
  // line of the bucket table.
  static std::uint64_t column_of(std::uint64_t cell_key) { return cell_key >> (2 * kRowShift); }
  // A cell's bucket counted from its region's first.
  template <bool kInOrder>
  std::size_t bucket_in_region(std::uint64_t cell_key, const CellOrder& order) const {
    const std::uint64_t z = cell_key & kZMask;
    if constexpr (kInOrder) {
      const std::uint64_t y = (cell_key >> kRowShift) & kZMask, x = cell_key >> (2 * kRowShift);
      return static_cast<std::size_t>(x * order.plane_stride + y * order.row_stride + z + order.origin) &
             region_mask_;
    } else {
      const std::uint64_t row = cell_key >> kRowShift;
      return static_cast<std::size_t>(((row * 0x9E3779B97F4A7C15ull) >> 20) + z) & region_mask_;
    }
  }
  std::size_t bucket_in_region(std::uint64_t cell_key, const CellOrder& order) const {
    return order.in_order() ? bucket_in_region<true>(cell_key, order)
                            : bucket_in_region<false>(cell_key, order);
  }
  // The cell order for cells `column` wide along x and `cell` along y and z, when the population's
  // lower corners span about `extent_m` on each axis.
  CellOrder cell_order(double extent_m, double column_m, double cell_m, const RegionMap& regions) const;
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
  // Whether any of the buckets [first, first + count) of the region starting at bucket `region`
  // (wrapping at its end) holds a slot.
  bool any_occupied(std::size_t region, std::size_t first, std::size_t count) const {
    for (std::size_t d = 0; d < count; ++d) {
      const std::size_t b = region | ((first + d) & region_mask_);
      if ((occupied_[b >> 6] >> (b & 63)) & 1u) return true;
    }
    return false;
  }

  // A slot's word for the chord filter (step_chord.hpp): its reach [m] as a float rounded up to a
  // multiple of 8 in the last place, whose 3 freed bits hold the chord's direction bits (bit set: the
  // box's lower corner stands for the chord's start on that axis, and the upper one for its end). One
  // array, so a hit costs one line beyond the boxes the walk has just read.
  static std::uint32_t chord_word(float reach_m, std::uint32_t ends) {
    return ((std::bit_cast<std::uint32_t>(reach_m) + 7u) & ~7u) | ends;  // >= reach_m (>= 0, finite)
  }
  static float chord_word_reach_m(std::uint32_t word) { return std::bit_cast<float>(word); }
  static constexpr int kRowShift = 21;
  static constexpr std::uint64_t kZMask = (std::uint64_t{1} << kRowShift) - 1;

  // Crossing bits. Bits 0-2 (kCrossesX, y, z): the axes the box crosses into the next cell on. A box
  // that stays in its cell along an axis cannot overlap a box whose lower corner lies in a later cell on
  // that axis, so the walk skips those forward neighbours (exact: the same candidates, fewer cells
  // visited). kGhost (slots only): the slot is the ghost of a box that crosses in x into another
  // region's column (see kGhostRegionShift), and walks only the next-column rows.
  static constexpr std::uint32_t kCrossesX = 1, kGhost = 16;
  // A box that crosses in x into another region's column gets a ghost there, and its own slot drops
  // kCrossesX (its next-column rows are the ghost's). The key pass marks it in its bucket: the ghost's
  // region + 1 above kGhostRegionShift (0: no ghost), so the count and the scatter read one array.
  static constexpr unsigned kGhostRegionShift = 27;
  static constexpr std::uint32_t kBucketMask = (std::uint32_t{1} << kGhostRegionShift) - 1;
  std::uint32_t ghost_bucket(std::uint32_t key_pass_bucket) const {
    return (((key_pass_bucket >> kGhostRegionShift) - 1) << region_bits_) | (key_pass_bucket & region_mask_);
  }
  // One object's grown box (rounded outwards to floats), cell key, bucket, population index and chord
  // word: 48 bytes, and the whole record the sort moves, so sorting never reads another thread's boxes at
  // random.
  struct GridBox {
    float lo[3], hi[3];
    std::uint32_t crosses;  // crossing bits
    std::uint32_t index;
    std::uint64_t key;
    std::uint32_t chord;   // chord_word
    std::uint32_t bucket;  // its cell's (a ghost's: ghost_bucket), kept for the scatter and the sort
  };
  static_assert(sizeof(GridBox) == 48);

  double cell_size_m_ = 0.0, column_width_m_ = 0.0;
  CellOrder cell_order_;  // the last build's
  // The edge of the cube centred on the origin that holds the population's lower corners [m] but a few
  // far out, from the last build: each thread's histogram of max |corner coordinate| on every
  // kExtentStride-th object. (Only the cell order depends on it, never a result.)
  static constexpr std::size_t kExtentBins = 64, kExtentStride = 16;
  static constexpr double kDefaultExtent_m = 2.0e7;
  double next_extent_m_ = kDefaultExtent_m;
  std::vector<std::uint32_t> thread_extent_hist_;
  // The cell edges to try first in the next build: the candidates never depend on them (only on the
  // boxes), so carrying them from step to step changes no result, and saves a pass when they fit.
  double next_cell_m_ = 0.0, next_column_m_ = 0.0;
  std::size_t builds_ = 0, rekeyed_builds_ = 0;
  // The cell edge over the largest box edge (>= 1: coarser cells where the population is sparse).
  double coarsening_ = 1.0;
  std::size_t regions_ = 1, region_mask_ = 0, partitions_ = 1;
  int region_bits_ = 0, fine_bits_ = 0;
  // Thread t's run of partitions [first, last) in a team of `threads`: contiguous, in order (it sorts
  // them, and walks their slots first).
  std::pair<std::size_t, std::size_t> partition_run(std::size_t t, std::size_t threads) const {
    return {partitions_ * t / threads, partitions_ * (t + 1) / threads};
  }
  // The region of partition p (each region holds 2^(region_bits_ - fine_bits_) partitions).
  std::size_t region_of_partition(std::size_t p) const { return p >> (region_bits_ - fine_bits_); }
  // Where the regions' borders go: a histogram of the lower x corners of the last build's boxes
  // (kHistogramBins bins of hist_width_m_ from hist_origin_m_), summed over the threads. Its own
  // central range gives the next one's bins; the first spans the paper's domain.
  static constexpr std::size_t kHistogramBins = 256;
  static constexpr double kDefaultBinOrigin_m = -1.0e7, kDefaultBinWidth_m = 2.0e7 / kHistogramBins;
  std::vector<std::uint32_t> hist_;
  double hist_origin_m_ = kDefaultBinOrigin_m, hist_width_m_ = kDefaultBinWidth_m;
  std::vector<std::uint32_t> thread_hist_;  // per thread: its chunk's histogram
  std::size_t prepared_threads_ = 0;
  std::size_t slots_in_grid_ = 0;  // objects in the grid plus ghosts
  // Slots the slot arrays have room for (ghosts make them more than the objects).
  std::size_t slot_capacity_ = 0;
  void ensure_slot_capacity(std::size_t slots);
  // The box and key passes' output per object (population index), arrays so that the passes vectorise:
  // the grown box rounded to floats, the chord filter's reach and direction bits, the oversized flag;
  // the cell key, bucket and crossing bits (the scatter assembles them into GridBox records).
  std::vector<float> box_lo_[3], box_hi_[3], box_reach_;
  std::vector<std::uint32_t> box_flags_;
  std::vector<std::uint64_t> box_key_;
  std::vector<std::uint32_t> box_bucket_;
  std::vector<std::uint8_t> box_crosses_;
  // Per slot (bucket order): the boxes axis by axis (lower x, y, z, upper x, y, z), each padded by
  // kLanes entries so the walk's last group of lanes reads inside the array; keys; crossing bits;
  // population indices.
  std::vector<float> slot_box_[6];
  std::vector<std::uint64_t> slot_key_;
  std::vector<std::uint8_t> slot_crosses_;  // GridBox::crosses
  std::vector<std::uint32_t> slot_index_;
  std::vector<std::uint32_t> slot_chord_;  // GridBox::chord
  std::vector<HermiteHull> hull_;          // per object, with Hermite motion
  std::vector<char> oversized_flag_;
  std::vector<std::uint32_t> oversized_;     // population indices, ascending
  std::vector<std::uint32_t> bucket_start_;  // size buckets + 1
  std::vector<std::uint64_t> occupied_;      // one bit per bucket
  // Counting-sort scratch, two records per object (a box and its ghost at most): each thread's boxes
  // grouped by coarse partition in [2 begin, 2 end) of its chunk [begin, end), so the scatter writes no
  // cache line another thread writes and needs no other thread's counts (it runs before the barrier).
  std::vector<GridBox> scratch_;
  // Per thread and partition: its count and where its group starts in scratch_.
  std::vector<std::uint32_t> coarse_count_, group_start_, partition_start_;
  std::vector<std::vector<std::uint32_t>> thread_oversized_;
  std::vector<double> thread_edge_;  // per thread: the largest box edge of its chunk
  // Per thread: the occupied buckets of the partitions it sorted in the last build (of a team of
  // occupancy_team_), for the coarsening.
  std::vector<std::uint32_t> thread_occupied_;
  std::size_t occupancy_team_ = 0;
  std::vector<double> thread_sort_s_;  // per thread: the last build's sort [s]
  struct alignas(64) ThreadPass {
    double seconds = 0.0;     // the last build's passes over its chunk
    std::size_t objects = 0;  // in its chunk
  };
  std::vector<ThreadPass> thread_pass_;
  std::vector<double> chunk_cost_per_object_s_;  // per thread, smoothed, for a team of costed_chunk_team_
  std::size_t costed_chunk_team_ = 0;            // 0: none measured
  // Per region: its smoothed cost per slot [s] (0: none measured yet), for regions_ == costed_regions_.
  double cost_per_slot_s_[kMaxRegions] = {};
  std::size_t costed_regions_ = 0;
  // Per thread: the sort's bucket counts, then cursors, for the partition at hand (kept out of
  // bucket_start_, whose partition edges the walks of other regions read meanwhile).
  std::vector<std::vector<std::uint32_t>> thread_bucket_cursor_;
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
  std::size_t requested_regions_ = 0;  // set_regions
};

}  // namespace kessler
