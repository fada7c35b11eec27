// The grid's walk: each slot against the slots of its own cell and of the 13 forward neighbour cells it
// can reach (exact pruning: only the axes its box crosses into the next cell on), 16 box tests at once,
// then the chord filter (step_chord.hpp) on the box hits; and the oversized objects against every object.
// The same pragma as the other phases' files (grid_boxes.cpp): no value changes.
#pragma GCC optimize("no-trapping-math")

#include <algorithm>
#include <bit>
#include <cstring>
#include <type_traits>

#include "core/conjunctions/broad_phase_grid.hpp"
#include "core/conjunctions/grid_boxes.hpp"

#ifdef __AVX512F__
#include <immintrin.h>
#endif

namespace kessler {
namespace {

using grid::kFarOut_m;

// The walk's float pre-filter of the chord test runs on cells up to this edge [m] (the detector's are
// at most the 20,000 km domain): in larger ones its products could overflow.
constexpr double kFloatFilterMaxCell_m = 2.5e7;

}  // namespace

void BroadPhaseGrid::collect_oversized_pairs(std::size_t begin, std::size_t end,
                                             std::vector<CandidatePair>& out) const {
  const std::size_t n = box_key_.size();
  const float *lo_x = box_lo_[0].data(), *lo_y = box_lo_[1].data(), *lo_z = box_lo_[2].data();
  const float *hi_x = box_hi_[0].data(), *hi_y = box_hi_[1].data(), *hi_z = box_hi_[2].data();
  // The overlap tests a block at a time in vector lanes (a far-out object, common in real catalogs,
  // overlaps nothing), then the hits in order.
  constexpr std::size_t kBlock = 256;
  alignas(64) unsigned char hit[kBlock];
  for (std::size_t o = begin; o < end; ++o) {
    const std::size_t i = oversized_[o];
    const float a_lo_x = lo_x[i], a_lo_y = lo_y[i], a_lo_z = lo_z[i];
    const float a_hi_x = hi_x[i], a_hi_y = hi_y[i], a_hi_z = hi_z[i];
    // Whether object j's box overlaps object i's (bitwise ands: no branches in the vector lanes).
    auto overlaps = [&](std::size_t j) {
      return (a_lo_x <= hi_x[j]) & (lo_x[j] <= a_hi_x) & (a_lo_y <= hi_y[j]) & (lo_y[j] <= a_hi_y) &
             (a_lo_z <= hi_z[j]) & (lo_z[j] <= a_hi_z);
    };
    if (!(a_lo_x <= kFarOut_m && -kFarOut_m <= a_hi_x && a_lo_y <= kFarOut_m && -kFarOut_m <= a_hi_y &&
          a_lo_z <= kFarOut_m && -kFarOut_m <= a_hi_z)) {
      // Its box misses the cube that holds every grid box (far out): only the later oversized objects
      // can meet it, in the order the scan below would find them.
      for (std::size_t p = o + 1; p < oversized_.size(); ++p) {
        const std::size_t j = oversized_[p];
        if (overlaps(j)) keep_pair(out, static_cast<std::uint32_t>(i), static_cast<std::uint32_t>(j));
      }
      continue;
    }
    for (std::size_t j0 = 0; j0 < n; j0 += kBlock) {
      const std::size_t m = std::min(kBlock, n - j0);
      std::fill(hit + m, hit + kBlock, 0);
#pragma omp simd
      for (std::size_t d = 0; d < m; ++d) hit[d] = overlaps(j0 + d);
      for (std::size_t w = 0; w < m; w += 8) {
        std::uint64_t word;
        std::memcpy(&word, hit + w, sizeof word);
        for (; word != 0; word &= word - 1) {
          const std::size_t j = j0 + w + static_cast<std::size_t>(std::countr_zero(word)) / 8;
          // Oversized with oversized: once, from the lower index.
          if (j == i || (oversized_flag_[j] && j < i)) continue;
          keep_pair(out, static_cast<std::uint32_t>(i), static_cast<std::uint32_t>(j));
        }
      }
    }
  }
}

#ifdef __AVX512F__
// GCC 12's intrinsics start some results from _mm512_undefined_*(), which -Wmaybe-uninitialized
// mistakes for a read of an uninitialised value once inlined.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"

void BroadPhaseGrid::filter_hits(HitBatch& hits, std::vector<CandidatePair>& out) const {
  const float *lo0 = slot_box_[0].data(), *lo1 = slot_box_[1].data(), *lo2 = slot_box_[2].data();
  const float *hi0 = slot_box_[3].data(), *hi1 = slot_box_[4].data(), *hi2 = slot_box_[5].data();
  const std::uint32_t* chord = slot_chord_.data();
  const std::uint64_t* key = slot_key_.data();
  const std::size_t count = hits.count;
  // Each hit is kept when slot m is in the cell asked for (buckets hold other cells too: without this
  // check a pair could be found from both sides) and the chord filter (step_chord.hpp) keeps the pair.
  // A slot's line for the filter is the corners of its box chosen by its direction bits: rising ? lo
  // : hi without a branch (the bits are random), exact since lo - hi of two floats is exact in double.
  // Eight hits at once, the same operations in the same order as the portable code below (so the
  // same outcome bit for bit), on slots gathered from the arrays.
  for (std::size_t h = 0; h < count; h += 8) {
    const __mmask8 valid = count - h >= 8 ? __mmask8{0xFF} : static_cast<__mmask8>((1u << (count - h)) - 1u);
    const __m256i self = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(hits.self + h));
    const __m256i other = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(hits.other + h));
    const __m512d zero = _mm512_setzero_pd();
    auto gather = [&](const float* array, __m256i slots) {
      return _mm512_cvtps_pd(_mm256_mmask_i32gather_ps(_mm256_setzero_ps(), valid, slots, array, 4));
    };
    // A slot's line and its reach, from its box and its chord word.
    auto line = [&](__m256i slots, __m512d start[3], __m512d end[3], __m512d& reach) {
      const __m256i word = _mm256_mmask_i32gather_epi32(_mm256_setzero_si256(), valid, slots, chord, 4);
      reach = _mm512_cvtps_pd(_mm256_castsi256_ps(word));
      const float* const lo[3] = {lo0, lo1, lo2};
      const float* const hi[3] = {hi0, hi1, hi2};
      for (int axis = 0; axis < 3; ++axis) {
        const __m512d l = gather(lo[axis], slots), u = gather(hi[axis], slots);
        const __m512d rising =
            _mm512_cvtepi32_pd(_mm256_and_si256(_mm256_srli_epi32(word, axis), _mm256_set1_epi32(1)));
        start[axis] = _mm512_add_pd(u, _mm512_mul_pd(rising, _mm512_sub_pd(l, u)));
        end[axis] = _mm512_add_pd(l, _mm512_mul_pd(rising, _mm512_sub_pd(u, l)));
      }
    };
    __m512d a0[3], a1[3], b0[3], b1[3], reach_a, reach_b;
    line(self, a0, a1, reach_a);
    line(other, b0, b1, reach_b);
    // chords_may_come_within, lane by lane.
    __m512d c0[3], u[3], uu = zero, c0u = zero, c0c0 = zero;
    for (int axis = 0; axis < 3; ++axis) {
      c0[axis] = _mm512_sub_pd(a0[axis], b0[axis]);
      u[axis] = _mm512_sub_pd(_mm512_sub_pd(a1[axis], b1[axis]), c0[axis]);
      uu = _mm512_add_pd(uu, _mm512_mul_pd(u[axis], u[axis]));
      c0u = _mm512_add_pd(c0u, _mm512_mul_pd(c0[axis], u[axis]));
      c0c0 = _mm512_add_pd(c0c0, _mm512_mul_pd(c0[axis], c0[axis]));
    }
    const __m512d t = _mm512_min_pd(_mm512_max_pd(_mm512_sub_pd(zero, c0u), zero), uu);
    const __m512d reach_sum = _mm512_add_pd(_mm512_add_pd(reach_a, reach_b), _mm512_set1_pd(kChordMargin_m));
    const __m512d left =
        _mm512_add_pd(_mm512_mul_pd(uu, c0c0), _mm512_mul_pd(t, _mm512_add_pd(_mm512_add_pd(c0u, c0u), t)));
    const __m512d right = _mm512_mul_pd(
        _mm512_add_pd(
            _mm512_mul_pd(_mm512_mul_pd(reach_sum, reach_sum), _mm512_set1_pd(1.0 + kChordRelativeSlack)),
            _mm512_mul_pd(_mm512_set1_pd(kChordCancellationSlack), c0c0)),
        uu);
    // The cell-key check only for the pairs the filter keeps (about 1 in 1,000 at 320k objects): the
    // keys are the one array of the other slot that the walk has not just read, so checking every hit
    // would cost a cache miss each.
    unsigned keep = _mm512_mask_cmp_pd_mask(valid, left, right, _CMP_LE_OQ);
    while (keep != 0) {
      const std::size_t hit = h + static_cast<std::size_t>(std::countr_zero(keep));
      keep &= keep - 1;
      if (key[hits.other[hit]] - hits.key_lo[hit] <= hits.span[hit])
        keep_pair(out, slot_index_[hits.self[hit]], slot_index_[hits.other[hit]]);
    }
  }
  hits.count = 0;
}

void BroadPhaseGrid::pair_with_slots(std::size_t k, std::size_t first, std::size_t last, std::uint64_t key_lo,
                                     std::uint64_t span, HitBatch& hits,
                                     std::vector<CandidatePair>& out) const {
  if (last <= first) return;
  const float *lo0 = slot_box_[0].data(), *lo1 = slot_box_[1].data(), *lo2 = slot_box_[2].data();
  const float *hi0 = slot_box_[3].data(), *hi1 = slot_box_[4].data(), *hi2 = slot_box_[5].data();
  const float a_lo0 = lo0[k], a_lo1 = lo1[k], a_lo2 = lo2[k], a_hi0 = hi0[k], a_hi1 = hi1[k], a_hi2 = hi2[k];
  // 16 box tests at once into a mask register (ordered compares: false with NaN, as the portable test
  // below); slots past `last` are read (the arrays are padded) and masked off (they may be another
  // region's, which its sort may be writing meanwhile: no result depends on their lanes). Even a range of one
  // or two slots is cheaper this way than one slot at a time.
  static_assert(kLanes == 16);
  const __m512 lo0_a = _mm512_set1_ps(a_lo0), lo1_a = _mm512_set1_ps(a_lo1), lo2_a = _mm512_set1_ps(a_lo2);
  const __m512 hi0_a = _mm512_set1_ps(a_hi0), hi1_a = _mm512_set1_ps(a_hi1), hi2_a = _mm512_set1_ps(a_hi2);
  const __m512i self = _mm512_set1_epi32(static_cast<int>(k));
  const __m512i span_lanes = _mm512_set1_epi32(static_cast<int>(span));
  const __m512i key_lo_lanes = _mm512_set1_epi64(static_cast<long long>(key_lo));
  const __m512i lane = _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
  // The chord filter's cheap float version on the group's lanes, against slot k's line (see
  // chords_may_come_within_float): nearly every box hit fails it, so only its survivors go to the batch,
  // where the double filter decides.
  const std::uint32_t* chord = slot_chord_.data();
  const std::uint32_t word_a = chord[k];
  // Slot k's line, without a branch (its direction bits are random): where the filter runs on every
  // group, once; elsewhere only for the groups that hit, which are few.
  // (Both lambdas are forced inline: outlined, as GCC may do, they read the broadcast registers through
  // memory, and the walk slows down markedly. For the same reason this function is not split further.)
  __m512 start_a[3], end_a[3];
  auto self_line = [&]() __attribute__((always_inline)) {
    const __m512 lo_a[3] = {lo0_a, lo1_a, lo2_a}, hi_a[3] = {hi0_a, hi1_a, hi2_a};
    for (int axis = 0; axis < 3; ++axis) {
      const auto rising = static_cast<__mmask16>(0u - ((word_a >> axis) & 1u));
      start_a[axis] = _mm512_mask_blend_ps(rising, hi_a[axis], lo_a[axis]);
      end_a[axis] = _mm512_mask_blend_ps(rising, lo_a[axis], hi_a[axis]);
    }
  };
  // Overlapping boxes' corners are within 2 cell edges on each axis, so the pairs' relative lines within
  // 3.5. Past kFloatFilterMaxCell_m the float filter's products could overflow: every box hit then goes
  // to the double filter.
  const double widest_edge_m = std::max(cell_size_m_, column_width_m_);
  const float filter_extent_m = static_cast<float>(3.5 * widest_edge_m);
  const __mmask16 filter_off = widest_edge_m <= kFloatFilterMaxCell_m ? 0 : 0xFFFF;
  const float* const lo_arrays[3] = {lo0, lo1, lo2};
  const float* const hi_arrays[3] = {hi0, hi1, hi2};
  // Dense regions hit boxes in most groups of lanes, at random: there the float filter runs on every
  // group without a branch (a branch on the box hits would be mispredicted half the time). Sparse
  // regions, and the long ranges of dense debris clouds, hit in almost none: there it runs only on
  // groups that hit (a branch predicted right). Which regime holds is read from the hit rate so far;
  // either way the batch gets the same hits.
  std::size_t groups = 0, found = 0;
  auto walk = [&](auto filter_every_group) __attribute__((always_inline)) {
    if constexpr (decltype(filter_every_group)::value) self_line();
    for (std::size_t base = first; base < last; base += kLanes, ++groups) {
      __m512 lo[3], hi[3];
      for (int axis = 0; axis < 3; ++axis) {
        lo[axis] = _mm512_loadu_ps(lo_arrays[axis] + base);
        hi[axis] = _mm512_loadu_ps(hi_arrays[axis] + base);
      }
      __mmask16 hit = _mm512_cmp_ps_mask(lo0_a, hi[0], _CMP_LE_OQ);
      hit = _mm512_mask_cmp_ps_mask(hit, lo[0], hi0_a, _CMP_LE_OQ);
      hit = _mm512_mask_cmp_ps_mask(hit, lo1_a, hi[1], _CMP_LE_OQ);
      hit = _mm512_mask_cmp_ps_mask(hit, lo[1], hi1_a, _CMP_LE_OQ);
      hit = _mm512_mask_cmp_ps_mask(hit, lo2_a, hi[2], _CMP_LE_OQ);
      hit = _mm512_mask_cmp_ps_mask(hit, lo[2], hi2_a, _CMP_LE_OQ);
      if (last - base < kLanes) hit &= static_cast<__mmask16>((1u << (last - base)) - 1u);
      if constexpr (!decltype(filter_every_group)::value) {
        if (hit == 0) continue;
        self_line();
      }
      found += static_cast<std::size_t>(std::popcount(static_cast<unsigned>(hit)));
      const __m512i word = _mm512_loadu_si512(chord + base);
      __m512 start_b[3], end_b[3];
      for (int axis = 0; axis < 3; ++axis) {
        const __mmask16 rising = _mm512_test_epi32_mask(word, _mm512_set1_epi32(1 << axis));
        start_b[axis] = _mm512_mask_blend_ps(rising, hi[axis], lo[axis]);
        end_b[axis] = _mm512_mask_blend_ps(rising, lo[axis], hi[axis]);
      }
      const __mmask16 keep =
          hit & (chords_may_come_within_float(start_a, end_a, _mm512_set1_ps(chord_word_reach_m(word_a)),
                                              start_b, end_b, _mm512_castsi512_ps(word), filter_extent_m) |
                 filter_off);
      if (keep == 0) continue;  // nearly always: a branch predicted right
      // The survivors' slots, packed, go to the batch's end, and the range's own values into all 16
      // entries there, of which the first popcount(keep) count. (The compress is done in a register:
      // its store form is slow on some cores.)
      const std::size_t at = hits.count;
      const __m512i slots = _mm512_add_epi32(_mm512_set1_epi32(static_cast<int>(base)), lane);
      _mm512_storeu_si512(hits.other + at, _mm512_maskz_compress_epi32(keep, slots));
      _mm512_storeu_si512(hits.self + at, self);
      _mm512_storeu_si512(hits.span + at, span_lanes);
      _mm512_storeu_si512(hits.key_lo + at, key_lo_lanes);
      _mm512_storeu_si512(hits.key_lo + at + 8, key_lo_lanes);
      hits.count = at + static_cast<std::size_t>(std::popcount(static_cast<unsigned>(keep)));
      if (hits.nearly_full()) filter_hits(hits, out);
    }
  };
  if (hits.dense())
    walk(std::true_type{});
  else
    walk(std::false_type{});
  hits.record(groups, found);
}
#pragma GCC diagnostic pop

#else

void BroadPhaseGrid::filter_hits(HitBatch& hits, std::vector<CandidatePair>& out) const {
  const float *lo0 = slot_box_[0].data(), *lo1 = slot_box_[1].data(), *lo2 = slot_box_[2].data();
  const float *hi0 = slot_box_[3].data(), *hi1 = slot_box_[4].data(), *hi2 = slot_box_[5].data();
  const std::uint32_t* chord = slot_chord_.data();
  const std::uint64_t* key = slot_key_.data();
  const std::size_t count = hits.count;
  // Each hit is kept when slot m is in the cell asked for (buckets hold other cells too: without this
  // check a pair could be found from both sides) and the chord filter (step_chord.hpp) keeps the pair.
  // A slot's line for the filter is the corners of its box chosen by its direction bits: rising ? lo
  // : hi without a branch (the bits are random), exact since lo - hi of two floats is exact in double.
  auto line = [&](std::uint32_t k, double start[3], double end[3]) {
    const std::uint32_t ends = chord[k];
    const float* const lo[3] = {lo0, lo1, lo2};
    const float* const hi[3] = {hi0, hi1, hi2};
    for (int axis = 0; axis < 3; ++axis) {
      const double l = lo[axis][k], u = hi[axis][k];
      const double rising = static_cast<double>((ends >> axis) & 1u);
      start[axis] = u + rising * (l - u);
      end[axis] = l + rising * (u - l);
    }
  };
  for (std::size_t h = 0; h < count; ++h) {
    const std::uint32_t k = hits.self[h], m = hits.other[h];
    double a0[3], a1[3], b0[3], b1[3];
    line(k, a0, a1);
    line(m, b0, b1);
    if (chords_may_come_within(a0, a1, chord_word_reach_m(chord[k]), b0, b1, chord_word_reach_m(chord[m])) &&
        key[m] - hits.key_lo[h] <= hits.span[h])
      keep_pair(out, slot_index_[k], slot_index_[m]);
  }
  hits.count = 0;
}

void BroadPhaseGrid::pair_with_slots(std::size_t k, std::size_t first, std::size_t last, std::uint64_t key_lo,
                                     std::uint64_t span, HitBatch& hits,
                                     std::vector<CandidatePair>& out) const {
  if (last <= first) return;
  const float *lo0 = slot_box_[0].data(), *lo1 = slot_box_[1].data(), *lo2 = slot_box_[2].data();
  const float *hi0 = slot_box_[3].data(), *hi1 = slot_box_[4].data(), *hi2 = slot_box_[5].data();
  const float a_lo0 = lo0[k], a_lo1 = lo1[k], a_lo2 = lo2[k], a_hi0 = hi0[k], a_hi1 = hi1[k], a_hi2 = hi2[k];
  auto add_hit = [&](std::size_t m) {
    hits.self[hits.count] = static_cast<std::uint32_t>(k);
    hits.other[hits.count] = static_cast<std::uint32_t>(m);
    hits.span[hits.count] = static_cast<std::uint32_t>(span);
    hits.key_lo[hits.count] = key_lo;
    if (++hits.count == HitBatch::kCapacity) filter_hits(hits, out);
  };
  // Short ranges (sparse populations) one slot at a time: the lanes' fixed cost would dominate.
  if (last - first < kLanes / 2) {
    for (std::size_t m = first; m < last; ++m) {
      const bool overlap = (a_lo0 <= hi0[m]) & (lo0[m] <= a_hi0) & (a_lo1 <= hi1[m]) & (lo1[m] <= a_hi1) &
                           (a_lo2 <= hi2[m]) & (lo2[m] <= a_hi2);
      if (overlap) add_hit(m);
    }
    return;
  }
  for (std::size_t base = first; base < last; base += kLanes) {
    // kLanes box tests at once, without branches (slots past `last` are read, then masked off).
    unsigned char hit[kLanes];
#pragma omp simd
    for (std::size_t l = 0; l < kLanes; ++l) {
      const std::size_t m = base + l;
      hit[l] = static_cast<unsigned char>((a_lo0 <= hi0[m]) & (lo0[m] <= a_hi0) & (a_lo1 <= hi1[m]) &
                                          (lo1[m] <= a_hi1) & (a_lo2 <= hi2[m]) & (lo2[m] <= a_hi2));
    }
    std::uint64_t word[kLanes / 8];
    std::memcpy(word, hit, sizeof hit);
    for (std::size_t w = 0; w < kLanes / 8; ++w) {
      for (std::uint64_t bits = word[w]; bits != 0; bits &= bits - 1) {
        const std::size_t m = base + 8 * w + static_cast<std::size_t>(std::countr_zero(bits)) / 8;
        if (m >= last) break;
        add_hit(m);
      }
    }
  }
}

#endif

void BroadPhaseGrid::pair_with_buckets(std::size_t k, std::size_t region, std::size_t first,
                                       std::size_t count, std::size_t from, std::uint64_t key_lo,
                                       std::uint64_t span, HitBatch& hits,
                                       std::vector<CandidatePair>& out) const {
  if (first + count <= region_mask_ + 1) {
    // One contiguous range (`from` lies in the first bucket or before it).
    pair_with_slots(k, std::max<std::size_t>(bucket_start_[region + first], from),
                    bucket_start_[region + first + count], key_lo, span, hits, out);
  } else {
    for (std::size_t d = 0; d < count; ++d) {  // wraps around the end of the region
      const std::size_t b = region | ((first + d) & region_mask_);
      pair_with_slots(k, d == 0 ? std::max<std::size_t>(bucket_start_[b], from) : bucket_start_[b],
                      bucket_start_[b + 1], key_lo, span, hits, out);
    }
  }
}

void BroadPhaseGrid::collect_pairs(std::size_t slot_begin, std::size_t slot_end,
                                   std::vector<CandidatePair>& out) const {
  HitBatch hits;
  const bool in_order = cells_in_order();
  auto collect_in = [&](std::size_t first, std::size_t last, std::size_t region) {
    in_order ? collect_pairs_in<true>(first, last, region, hits, out)
             : collect_pairs_in<false>(first, last, region, hits, out);
  };
  if (regions_ == 1) {
    collect_in(slot_begin, slot_end, 0);
  } else {
    // Region by region (each holds a contiguous run of slots, its ghosts among them), so the region of
    // every row a slot looks up is known.
    for (std::size_t r = 0; r < regions_; ++r) {
      const std::size_t region = r << region_bits_;
      const std::size_t first = std::max<std::size_t>(slot_begin, bucket_start_[region]);
      const std::size_t last = std::min<std::size_t>(slot_end, bucket_start_[region + region_mask_ + 1]);
      if (first < last) collect_in(first, last, region);
    }
  }
  filter_hits(hits, out);
}

template <bool kInOrder>
void BroadPhaseGrid::collect_pairs_in(std::size_t slot_begin, std::size_t slot_end, std::size_t region,
                                      HitBatch& hits, std::vector<CandidatePair>& out) const {
  // In order, the forward rows' buckets are at fixed offsets from the cell's own.
  const grid::CellOrder order = cell_order_;
  const std::uint64_t row_offsets[4] = {order.row_stride, order.plane_stride - order.row_stride,
                                        order.plane_stride, order.plane_stride + order.row_stride};
  for (std::size_t k = slot_begin; k < slot_end; ++k) {
    const std::uint64_t key = slot_key_[k];
    const std::uint32_t crosses = slot_crosses_[k];
    // z cells of a neighbour row: z - 1 and z, and z + 1 only if the box reaches into the next z cell.
    const std::size_t z_cells = (crosses & 4u) ? 3 : 2;
    // A ghost walks only the next column's rows (1-3): its own column's are its box's, in the last
    // region. `walks` has kGhost set for the slots that walk their own column.
    const std::uint32_t walks = crosses ^ grid::kGhost;
    // Own row: the same cell (slots after k) and the next z cell, in buckets b and b + 1.
    const std::size_t own = grid::bucket_in_region<kInOrder>(key, order, region_mask_);
    if (walks & grid::kGhost) pair_with_buckets(k, region, own, z_cells - 1, k + 1, key, 1, hits, out);
    // The forward rows, z cells -1..+1: buckets b' - 1 .. b' + 1. Rows at y + 1 only if the box
    // reaches into the next y cell, rows at x + 1 only if it reaches into the next x cell (in this
    // region: a box whose next column is another region's has dropped kCrossesX, and its ghost there
    // walks those rows).
    for (int r = 0; r < 4; ++r) {
      const std::uint32_t needs = grid::kForwardRowNeeds[r] | (r == 0 ? grid::kGhost : 0u);
      if ((walks & needs) != needs) continue;
      const std::uint64_t centre = key + grid::kForwardRows[r];
      const std::size_t first =
          ((kInOrder ? own + row_offsets[r] : grid::bucket_in_region<false>(centre, order, region_mask_)) -
           1) &
          region_mask_;
      // Many neighbour rows are empty: the occupancy bitmap answers.
      if (!any_occupied(region, first, z_cells)) continue;
      pair_with_buckets(k, region, first, z_cells, 0, centre - 1, z_cells - 1, hits, out);
    }
  }
}

}  // namespace kessler
