// The chord filter that the broad phase runs on each pair whose boxes overlap (step_chord.hpp), through
// the grid itself, with Hermite motion on curved arcs: it must never drop a pair the narrow phase
// reports (whatever the size of the coordinates, whose float rounding grows with them), and it must drop
// pairs that cross the same place at different times, or it buys nothing.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <random>
#include <set>
#include <utility>
#include <vector>

#include "core/conjunctions/broad_phase_grid.hpp"
#include "core/conjunctions/narrow_phase_hermite.hpp"
#include "core/conjunctions/step_chord.hpp"
#include "tests/conjunctions/random_encounter.hpp"

namespace kessler {
namespace {

struct Tally {
  int reported = 0;       // pairs the narrow phase reports
  int boxes_overlap = 0;  // pairs whose grown boxes overlap
  int listed = 0;         // pairs the grid lists
};

// `scenes` pairs of objects, each meeting near its own random point of a shell of `radius_m` at a random
// time of the step, at a miss distance spread around the threshold, each under a constant acceleration:
// gravity at the meeting point (the arcs bend by g dt^2 / 8), and for b up to 20 % more in a random
// direction, so that the relative motion bends too (hundreds of metres in a step) and the filter's
// deviation bound is needed; half of them offset in time by up to 5 s, so they cross the same place at
// different times. All scenes go through one grid build.
Tally run_scenes(int scenes, double radius_m, double dt, double threshold_m, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0), unit(0.0, 1.0);
  StateArrays start, end;
  start.resize(2 * static_cast<std::size_t>(scenes));
  end.resize(2 * static_cast<std::size_t>(scenes));
  for (int scene = 0; scene < scenes; ++scene) {
    const testing::MeetingPoint point = testing::random_meeting_point(rng, radius_m);
    const double* meet = point.position_m;
    const double g = 3.986004418e14 / (radius_m * radius_m);
    double va[3], vb[3], acc_a[3], acc_b[3], miss[3];
    for (int k = 0; k < 3; ++k) {
      va[k] = 7500.0 * u(rng);
      vb[k] = 7500.0 * u(rng);
      acc_a[k] = point.gravity_m_s2[k];
      acc_b[k] = acc_a[k] + 0.2 * g * u(rng);
      miss[k] = u(rng) * threshold_m * 1.2;
    }
    const double t_meet = dt * unit(rng);
    const double late = scene % 2 == 0 ? 0.0 : 5.0 * u(rng);  // b passes the point `late` s later
    const std::size_t a = 2 * static_cast<std::size_t>(scene), b = a + 1;
    double pa[3], pb[3];
    for (int k = 0; k < 3; ++k) {
      // Backwards from the meeting point: p(t) = p0 + v0 t + acc t^2 / 2 with p(t_meet) = meet, so
      // p0 = meet - v(t_meet) t_meet + acc t_meet^2 / 2, v0 = v(t_meet) - acc t_meet.
      pa[k] = meet[k] - va[k] * t_meet + 0.5 * acc_a[k] * t_meet * t_meet;
      va[k] -= acc_a[k] * t_meet;
      const double tb = t_meet + late;
      pb[k] = meet[k] + miss[k] - vb[k] * tb + 0.5 * acc_b[k] * tb * tb;
      vb[k] -= acc_b[k] * tb;
    }
    auto place = [&](std::size_t i, const double p[3], const double v[3], const double acc[3]) {
      const Eigen::Vector3d p0(p[0], p[1], p[2]), v0(v[0], v[1], v[2]), g3(acc[0], acc[1], acc[2]);
      start.set(i, p0, v0);
      end.set(i, p0 + v0 * dt + 0.5 * g3 * dt * dt, v0 + g3 * dt);
    };
    place(a, pa, va, acc_a);
    place(b, pb, vb, acc_b);
  }
  ThresholdShare shares;
  shares.fixed_m = 0.5 * threshold_m;
  BroadPhaseGrid grid;
  grid.build(StepEnds{0.0, dt, &start, &end}, NarrowPhase::kHermite, shares,
             BroadPhaseGrid::cutoff_bound_m(dt, 0.0));
  std::vector<CandidatePair> out;
  grid.collect_pairs(0, grid.slot_count(), out);
  std::set<std::pair<std::uint32_t, std::uint32_t>> listed;
  for (const CandidatePair& p : out) listed.insert({std::min(p.i, p.j), std::max(p.i, p.j)});

  Tally tally;
  for (int scene = 0; scene < scenes; ++scene) {
    const std::uint32_t a = 2 * static_cast<std::uint32_t>(scene), b = a + 1;
    const ObjectStep oa = gather_object_step(start, end, a), ob = gather_object_step(start, end, b);
    PairMinimum minima[kMaxMinimaPerStep];
    const bool in_grid = listed.count({a, b}) > 0;
    if (hermite_minima(oa, ob, dt, threshold_m, minima) > 0) {
      ++tally.reported;
      EXPECT_TRUE(in_grid) << "dropped a reported pair: scene " << scene << ", distance "
                           << minima[0].distance_m;
    }
    // The Bezier hulls' boxes, grown by the shares: the pairs the grid meets before its filter.
    bool overlap = true;
    for (int k = 0; k < 3; ++k) {
      auto range = [&](const ObjectStep& o, double& lo, double& hi) {
        const double c[4] = {o.p0[k], o.p0[k] + dt / 3.0 * o.v0[k], o.p1[k] - dt / 3.0 * o.v1[k], o.p1[k]};
        lo = std::min(std::min(c[0], c[1]), std::min(c[2], c[3])) - 0.5 * threshold_m;
        hi = std::max(std::max(c[0], c[1]), std::max(c[2], c[3])) + 0.5 * threshold_m;
      };
      double alo, ahi, blo, bhi;
      range(oa, alo, ahi);
      range(ob, blo, bhi);
      overlap = overlap && alo <= bhi && blo <= ahi;
    }
    tally.boxes_overlap += overlap;
    tally.listed += in_grid;
  }
  std::printf("  %d scenes: %d reported, %d boxes overlap, %d listed\n", scenes, tally.reported,
              tally.boxes_overlap, tally.listed);
  return tally;
}

TEST(StepChord, NeverDropsAReportedPairInLowOrbit) {
  const Tally t = run_scenes(20000, 6.9e6, 30.0, 20.0, 1);
  EXPECT_GT(t.reported, 1000);  // many pairs within the threshold, some of them just inside
  EXPECT_GT(t.boxes_overlap, 19000);
  // Half the pairs pass seconds apart: most of those are ruled out (a filter keeping every pair whose
  // boxes overlap would list them all).
  EXPECT_LT(t.listed, t.boxes_overlap - 7000);
}

TEST(StepChord, NeverDropsAReportedPairFarOutWhereFloatsAreCoarse) {
  // At 42,000 km a float's spacing is 4 m, more than a 2 m threshold: only the rounding bounds keep
  // these pairs.
  const Tally t = run_scenes(20000, 4.2e7, 30.0, 2.0, 2);
  EXPECT_GT(t.reported, 1000);
  EXPECT_GT(t.boxes_overlap, 19000);
  EXPECT_LT(t.listed, t.boxes_overlap - 7000);
}

TEST(StepChord, NeverDropsAReportedPairAtAFiveKilometreScreening) {
  const Tally t = run_scenes(20000, 7.0e6, 30.0, 5000.0, 3);
  EXPECT_GT(t.reported, 1000);
  EXPECT_GT(t.boxes_overlap, 19000);
  EXPECT_LT(t.listed, t.boxes_overlap - 2000);  // a threshold of 5 km keeps more of them
}

// The walk's single-precision pre-filter (chords_may_come_within_float) against the double test, on
// relative lines that pass the origin at a miss distance spread around the summed reach (most within
// 0.1 % of it, where rounding decides), in low orbit and at 42,000 km: it must keep every pair the
// double test keeps, and drop most of those that pass at 3 reaches or more, or it buys nothing.
TEST(StepChord, FloatPreFilterKeepsEveryPairTheDoubleTestKeeps) {
#ifndef __AVX512F__
  GTEST_SKIP() << "the float pre-filter is built with AVX-512 only";
#else
  constexpr int kLanes = 16;
  const double cell_m = 240e3, extent_m = 3.5 * cell_m;
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0), unit(0.0, 1.0);
  std::normal_distribution<double> normal(0.0, 1.0);
  auto random_vector = [&](double length) {
    std::array<double, 3> v;
    double norm = 0.0;
    do {
      for (double& c : v) c = u(rng);
      norm = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    } while (norm > 1.0 || norm < 1e-3);
    for (double& c : v) c *= length / norm;
    return v;
  };
  for (const double radius_m : {6.9e6, 4.2e7}) {
    int double_kept = 0, float_dropped_kept = 0, far = 0, far_dropped = 0;
    for (int batch = 0; batch < 4000; ++batch) {
      alignas(64) float lanes[14][kLanes];  // a0, a1, b0, b1 (x, y, z each), reach_a, reach_b
      bool double_keeps[kLanes];
      bool is_far[kLanes];
      for (int lane = 0; lane < kLanes; ++lane) {
        const float reach_a = static_cast<float>(1.0 + 2000.0 * unit(rng));
        const float reach_b = static_cast<float>(1.0 + 2000.0 * unit(rng));
        const double reach = double{reach_a} + double{reach_b};
        const double factor = lane % 2 == 0 ? 1.0 + 1e-3 * normal(rng) : 20.0 * unit(rng);
        // The relative line c(s) = miss + (s - s_min) u, closest to the origin at s_min.
        const auto rel = random_vector(4e5 * unit(rng));
        auto miss = random_vector(1.0);
        const double along = miss[0] * rel[0] + miss[1] * rel[1] + miss[2] * rel[2];
        const double rel2 = rel[0] * rel[0] + rel[1] * rel[1] + rel[2] * rel[2];
        double miss_norm = 0.0;
        for (int k = 0; k < 3; ++k) {
          miss[k] -= rel2 > 0.0 ? along / rel2 * rel[k] : 0.0;
          miss_norm += miss[k] * miss[k];
        }
        miss_norm = std::sqrt(miss_norm);
        const double s_min = -0.2 + 1.4 * unit(rng);
        const auto centre = random_vector(radius_m);
        const auto offset = random_vector(cell_m * unit(rng));
        const auto motion_b = random_vector(2.25e5 * unit(rng));
        float f[4][3];
        for (int k = 0; k < 3; ++k) {
          const double c0 = miss[k] / miss_norm * factor * reach - s_min * rel[k];
          const double b0 = centre[k] + offset[k], b1 = b0 + motion_b[k];
          f[0][k] = static_cast<float>(b0 + c0);
          f[1][k] = static_cast<float>(b1 + c0 + rel[k]);
          f[2][k] = static_cast<float>(b0);
          f[3][k] = static_cast<float>(b1);
        }
        double a0[3], a1[3], b0[3], b1[3];
        for (int k = 0; k < 3; ++k) {
          a0[k] = f[0][k], a1[k] = f[1][k], b0[k] = f[2][k], b1[k] = f[3][k];
          for (int end = 0; end < 4; ++end) lanes[3 * end + k][lane] = f[end][k];
        }
        lanes[12][lane] = reach_a;
        lanes[13][lane] = reach_b;
        double_keeps[lane] = chords_may_come_within(a0, a1, reach_a, b0, b1, reach_b);
        is_far[lane] = factor >= 3.0;
      }
      __m512 a0[3], a1[3], b0[3], b1[3];
      for (int k = 0; k < 3; ++k) {
        a0[k] = _mm512_load_ps(lanes[k]);
        a1[k] = _mm512_load_ps(lanes[3 + k]);
        b0[k] = _mm512_load_ps(lanes[6 + k]);
        b1[k] = _mm512_load_ps(lanes[9 + k]);
      }
      const __mmask16 keeps = chords_may_come_within_float(
          a0, a1, _mm512_load_ps(lanes[12]), b0, b1, _mm512_load_ps(lanes[13]), static_cast<float>(extent_m));
      for (int lane = 0; lane < kLanes; ++lane) {
        const bool float_keeps = (keeps >> lane) & 1u;
        double_kept += double_keeps[lane];
        float_dropped_kept += double_keeps[lane] && !float_keeps;
        far += is_far[lane];
        far_dropped += is_far[lane] && !float_keeps;
      }
    }
    std::printf("  radius %.0f km: double keeps %d, float drops %d of them; %d far, float drops %d\n",
                radius_m / 1e3, double_kept, float_dropped_kept, far, far_dropped);
    EXPECT_GT(double_kept, 10000);  // many pairs right at the reach
    EXPECT_EQ(float_dropped_kept, 0);
    EXPECT_GT(far_dropped, 0.9 * far);
  }
#endif
}

}  // namespace
}  // namespace kessler
