// The grid's counting sort: each thread counts and scatters its chunk's boxes into coarse partitions of
// its own part of the scratch (before the build's barrier: it needs no other thread's counts), then, after
// it, sorts a contiguous run of partitions by fine bucket into the slot arrays. The sort is stable, so the
// slots' order never depends on the number of threads.
// The same pragma as the other phases' files (grid_boxes.cpp): no value changes.
#pragma GCC optimize("no-trapping-math")

#include <algorithm>
#include <bit>
#include <type_traits>

#include "core/conjunctions/broad_phase_grid.hpp"
#include "core/conjunctions/grid_boxes.hpp"

#ifdef __AVX512F__
#include <immintrin.h>
// GCC 12's intrinsics start some results from _mm512_undefined_*(), which -Wmaybe-uninitialized
// mistakes for a read of an uninitialised value once inlined (here: the prefix sum, into the sort).
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif

namespace kessler {
namespace {

// counts[0, size) replaced by their running sum from `first` (the sum of those before each, plus first).
// With AVX-512, 16 at a time (a scan in a register: 4 shifted adds), since the one-at-a-time loop is a
// long chain of dependent adds; the sort's partitions hold a multiple of 64 buckets, so the scalar loop
// after it only serves other machines.
void exclusive_prefix_sum(std::uint32_t* counts, std::size_t size, std::uint32_t first) {
  std::size_t f = 0;
#ifdef __AVX512F__
  const __m512i zero = _mm512_setzero_si512(), last = _mm512_set1_epi32(15);
  __m512i carry = _mm512_set1_epi32(static_cast<int>(first));
  for (; f + 16 <= size; f += 16) {
    const __m512i c = _mm512_loadu_si512(counts + f);
    __m512i sum = _mm512_add_epi32(c, _mm512_alignr_epi32(c, zero, 15));  // + the lane below
    sum = _mm512_add_epi32(sum, _mm512_alignr_epi32(sum, zero, 14));      // + the 2 below those
    sum = _mm512_add_epi32(sum, _mm512_alignr_epi32(sum, zero, 12));
    sum = _mm512_add_epi32(sum, _mm512_alignr_epi32(sum, zero, 8));
    _mm512_storeu_si512(counts + f, _mm512_add_epi32(carry, _mm512_sub_epi32(sum, c)));
    carry = _mm512_add_epi32(carry, _mm512_permutexvar_epi32(last, sum));
  }
  first = static_cast<std::uint32_t>(_mm_cvtsi128_si32(_mm512_castsi512_si128(carry)));
#endif
  for (; f < size; ++f) {
    const std::uint32_t c = counts[f];
    counts[f] = first;
    first += c;
  }
}

}  // namespace

void BroadPhaseGrid::count_chunk(const ThreadBuild& b) {
  // The counts go to the shared array once, at the end: every thread reads all of them after the
  // barrier, so counting in place would pull the line back from other cores at each object.
  std::uint32_t local_counts[kMaxPartitions] = {};
  for (std::size_t i = b.begin; i < b.end; ++i) {
    if (oversized_flag_[i]) continue;
    const std::uint32_t bucket = box_bucket_[i];
    ++local_counts[(bucket & grid::kBucketMask) >> fine_bits_];
    if (bucket > grid::kBucketMask) ++local_counts[ghost_bucket(bucket) >> fine_bits_];  // ~1 % (2 regions)
  }
  std::copy(local_counts, local_counts + partitions_, b.counts);
}

void BroadPhaseGrid::scatter_chunk(const ThreadBuild& b) {
  // Whole records, grouped by partition in [2 begin, 2 end) of scratch_, read back in sequence by the
  // partition's sorter.
  const std::size_t begin = b.begin, end = b.end, partitions = partitions_;
  std::uint32_t at = static_cast<std::uint32_t>(2 * begin);
  std::uint32_t* group = &group_start_[b.t * partitions];
  std::uint32_t cursor[kMaxPartitions];
  for (std::size_t p = 0; p < partitions; ++p) {
    group[p] = cursor[p] = at;
    at += b.counts[p];
  }
  // Each record is built in registers from the passes' arrays (read in sequence) and stored in one go:
  // stored field by field, into lines that the other cores read in the last sort, the store queue
  // fills while those lines are fetched back. With a team, the line a record kAhead objects on goes to
  // is asked for ahead, for writing, so those fetches overlap (one thread, whose lines are its own, only
  // pays for the extra instructions).
  // A shared grid (set_share) keeps only its part's partitions: the others' groups stay unwritten, and
  // unread.
  const auto [own_first, own_last] = shared_partitions();
  const std::uint32_t fine_bits = static_cast<std::uint32_t>(fine_bits_);
  auto own = [&, first = own_first, count = own_last - own_first](std::uint32_t bucket) {
    return (bucket >> fine_bits) - first < count;
  };
  auto scatter = [&](auto ask_ahead, auto shared) {
    constexpr std::size_t kAhead = 16;
    for (std::size_t i = begin; i < end; ++i) {
      if constexpr (decltype(ask_ahead)::value) {
        if (i + kAhead < end) {
          const char* line = reinterpret_cast<const char*>(
              &scratch_[cursor[(box_bucket_[i + kAhead] & grid::kBucketMask) >> fine_bits_]]);
          __builtin_prefetch(line, 1);
          __builtin_prefetch(line + sizeof(GridBox), 1);  // a record may straddle two lines
        }
      }
      if (oversized_flag_[i]) continue;
      if constexpr (decltype(shared)::value) {  // neither the box nor its ghost in this part: skip early
        const std::uint32_t bucket = box_bucket_[i];
        if (!own(bucket & grid::kBucketMask) && (bucket <= grid::kBucketMask || !own(ghost_bucket(bucket))))
          continue;
      }
      GridBox box;
      for (int k = 0; k < 3; ++k) {
        box.lo[k] = box_lo_[k][i];
        box.hi[k] = box_hi_[k][i];
      }
      const std::uint32_t crosses = box_crosses_[i], bucket = box_bucket_[i];
      box.index = static_cast<std::uint32_t>(i);
      box.key = box_key_[i];
      box.chord = chord_word(box_reach_[i], box_flags_[i] & grid::kChordEndsMask);
      if (bucket > grid::kBucketMask) {  // ghosted: about 1 % of the boxes with 2 regions
        box.crosses = crosses | grid::kGhost;
        box.bucket = ghost_bucket(bucket);
        if (!decltype(shared)::value || own(box.bucket)) scratch_[cursor[box.bucket >> fine_bits_]++] = box;
        box.crosses = crosses & ~grid::kCrossesX;
      } else {
        box.crosses = crosses;
      }
      box.bucket = bucket & grid::kBucketMask;
      if (!decltype(shared)::value || own(box.bucket)) scratch_[cursor[box.bucket >> fine_bits_]++] = box;
    }
  };
  const bool shared = share_parts_ > 1;
  if (b.threads > 1)
    shared ? scatter(std::true_type{}, std::true_type{}) : scatter(std::true_type{}, std::false_type{});
  else
    shared ? scatter(std::false_type{}, std::true_type{}) : scatter(std::false_type{}, std::false_type{});
}

std::uint32_t BroadPhaseGrid::lay_out_partitions(const ThreadBuild& b) {
  // Slots: partitions in order, inside a partition the threads' groups in thread order (so population
  // order within each bucket, whatever the thread count). Every thread reads all counts and computes
  // the layout itself (no serial section).
  const std::size_t partitions = partitions_, fine_buckets = std::size_t{1} << fine_bits_;
  const auto [p_begin, p_end] = partition_run(b.t, b.threads);
  // A shared grid's partitions of other parts, which no thread here sorts: thread 0 writes their
  // starts (the walk of this part's last region reads the next one's as its end).
  const auto [own_first, own_last] = shared_partitions();
  std::uint32_t total_slots = 0;  // objects in the grid and ghosts
  for (std::size_t p = 0; p < partitions; ++p) {
    if ((p >= p_begin && p < p_end) || (b.t == 0 && (p < own_first || p >= own_last))) {
      partition_start_[p] = total_slots;
      // The partition's first bucket start, before any sort: the walk of the region below it reads it
      // as the end of its last bucket, and may begin before this partition is sorted (once every
      // thread has counted itself in layout_ready_ below).
      bucket_start_[p * fine_buckets] = total_slots;
    }
    for (std::size_t u = 0; u < b.threads; ++u) total_slots += coarse_count_[u * partitions + p];
  }
  if (b.t + 1 == b.threads) bucket_start_[regions_ << region_bits_] = total_slots;
  layout_ready_->count.fetch_add(1, std::memory_order_release);
  return total_slots;
}

void BroadPhaseGrid::sort_partitions(const ThreadBuild& b) {
  // Each thread sorts a contiguous run of partitions by fine bucket (stable), so the slot arrays'
  // lines are written by one thread each (no line shared but at the run's two ends).
  const std::size_t partitions = partitions_, fine_buckets = std::size_t{1} << fine_bits_;
  const auto [p_begin, p_end] = partition_run(b.t, b.threads);
  for (std::size_t p = p_begin; p < p_end; ++p) {
    if (b.threads > 1 && p + 1 < p_end) {
      // The next partition's records from the other threads, asked for while this one is sorted: they
      // sit in other cores' caches, and a group is too short for the hardware's stream prefetch.
      for (std::size_t u = 0; u < b.threads; ++u) {
        if (u == b.t) continue;
        const char* first = reinterpret_cast<const char*>(&scratch_[group_start_[u * partitions + p + 1]]);
        const std::size_t bytes = coarse_count_[u * partitions + p + 1] * sizeof(GridBox);
        for (std::size_t at = 0; at < bytes; at += 64) __builtin_prefetch(first + at);
      }
    }
    sort_partition(b, p);
    // Its region's walks may read it now (once the region's other partitions are sorted too).
    region_progress_[region_of_partition(p)].count.fetch_add(1, std::memory_order_release);
  }
  // The occupied cells (buckets) of this thread's partitions, for the next build's cell.
  std::uint32_t occupied = 0;
  for (std::size_t w = p_begin * fine_buckets / 64; w < p_end * fine_buckets / 64; ++w)
    occupied += static_cast<std::uint32_t>(std::popcount(occupied_[w]));
  thread_occupied_[b.t] = occupied;
}

void BroadPhaseGrid::sort_partition(const ThreadBuild& b, std::size_t p) {
  const std::size_t partitions = partitions_, fine_buckets = std::size_t{1} << fine_bits_;
  const std::size_t first_bucket = p * fine_buckets;
  std::uint32_t* const starts = &bucket_start_[first_bucket];
  std::uint32_t* const cursor = thread_bucket_cursor_[b.t].data();
  std::fill(cursor, cursor + fine_buckets, 0u);
  std::fill(&occupied_[first_bucket / 64], &occupied_[first_bucket / 64] + fine_buckets / 64, 0ull);
  // The partition's boxes: every thread's group, in thread order.
  auto each_box = [&](auto&& f) {
    for (std::size_t u = 0; u < b.threads; ++u) {
      const GridBox* group = &scratch_[group_start_[u * partitions + p]];
      const std::uint32_t count = coarse_count_[u * partitions + p];
      for (std::uint32_t m = 0; m < count; ++m) f(group[m]);
    }
  };
  each_box([&](const GridBox& box) {
    const std::size_t k = box.bucket;
    ++cursor[k - first_bucket];
    occupied_[k >> 6] |= std::uint64_t{1} << (k & 63);
  });
  exclusive_prefix_sum(cursor, fine_buckets, partition_start_[p]);
  // The starts (the first one is set already), then the scatter with the cursors.
  std::copy(cursor + 1, cursor + fine_buckets, starts + 1);
  each_box([&](const GridBox& box) {
    const std::uint32_t k = cursor[box.bucket - first_bucket]++;
    for (int axis = 0; axis < 3; ++axis) {
      slot_box_[axis][k] = box.lo[axis];
      slot_box_[3 + axis][k] = box.hi[axis];
    }
    slot_key_[k] = box.key;
    slot_crosses_[k] = static_cast<std::uint8_t>(box.crosses);
    slot_index_[k] = box.index;
    slot_chord_[k] = box.chord;
  });
}

}  // namespace kessler

#ifdef __AVX512F__
#pragma GCC diagnostic pop
#endif
