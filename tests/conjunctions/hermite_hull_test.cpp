// The single-precision hull test that the detector runs before the Hermite narrow phase: it must never
// drop a pair the narrow phase reports (whatever the size of the coordinates, whose float rounding grows
// with them), and it must drop pairs that pass at different times, or it buys nothing.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/conjunctions/hermite_hull.hpp"
#include "core/conjunctions/narrow_phase_hermite.hpp"
#include "tests/conjunctions/random_encounter.hpp"

namespace kessler {
namespace {

// A straight-ish arc: start state, and the end state a step later under a constant acceleration.
ObjectStep arc(const double p[3], const double v[3], const double a[3], double dt) {
  ObjectStep o;
  for (int k = 0; k < 3; ++k) {
    o.p0[k] = p[k];
    o.v0[k] = v[k];
    o.p1[k] = p[k] + v[k] * dt + 0.5 * a[k] * dt * dt;
    o.v1[k] = v[k] + a[k] * dt;
  }
  return o;
}

struct Tally {
  int reported = 0, kept = 0, dropped = 0;
};

// Pairs that meet near a random point of a shell of `radius_m`, at a random time of the step, at a miss
// distance spread around the threshold; half of them offset in time by a few seconds, so they cross
// the same place at different times.
Tally run_pairs(double radius_m, double dt, double threshold_m, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0), unit(0.0, 1.0);
  Tally tally;
  for (int trial = 0; trial < 20000; ++trial) {
    const testing::MeetingPoint point = testing::random_meeting_point(rng, radius_m);
    const double* meet = point.position_m;
    double va[3], vb[3], acc[3], miss[3];
    for (int k = 0; k < 3; ++k) {
      va[k] = 7500.0 * u(rng);
      vb[k] = 7500.0 * u(rng);
      acc[k] = point.gravity_m_s2[k];
      miss[k] = u(rng) * threshold_m * 1.2;
    }
    const double t_meet = dt * unit(rng);
    const double late = trial % 2 == 0 ? 0.0 : 5.0 * u(rng);  // b passes the point `late` s later
    double pa[3], pb[3];
    for (int k = 0; k < 3; ++k) {
      pa[k] = meet[k] - va[k] * t_meet + 0.5 * acc[k] * t_meet * t_meet;
      const double tb = t_meet + late;
      pb[k] = meet[k] + miss[k] - vb[k] * tb + 0.5 * acc[k] * tb * tb;
    }
    const ObjectStep a = arc(pa, va, acc, dt), b = arc(pb, vb, acc, dt);
    PairMinimum minima[kMaxMinimaPerStep];
    const int found = hermite_minima(a, b, dt, threshold_m, minima);
    const bool kept =
        hulls_may_come_within(hermite_hull(a, dt, 0.5 * threshold_m), hermite_hull(b, dt, 0.5 * threshold_m));
    if (found > 0) {
      ++tally.reported;
      EXPECT_TRUE(kept) << "dropped a reported pair: trial " << trial << ", distance "
                        << minima[0].distance_m;
    }
    kept ? ++tally.kept : ++tally.dropped;
  }
  return tally;
}

TEST(HermiteHull, NeverDropsAReportedPairInLowOrbit) {
  const Tally t = run_pairs(6.9e6, 30.0, 20.0, 1);
  EXPECT_GT(t.reported, 1000);  // many pairs within the threshold, some of them just inside
  EXPECT_GT(t.dropped, 5000);   // and those passing at different times are ruled out
}

TEST(HermiteHull, NeverDropsAReportedPairFarOutWhereFloatsAreCoarse) {
  // At 42,000 km a float's spacing is 4 m, more than a 2 m threshold: only the slack keeps these pairs.
  const Tally t = run_pairs(4.2e7, 30.0, 2.0, 2);
  EXPECT_GT(t.reported, 1000);
  EXPECT_GT(t.dropped, 5000);
}

TEST(HermiteHull, NeverDropsAReportedPairAtAFiveKilometreScreening) {
  const Tally t = run_pairs(7.0e6, 30.0, 5000.0, 3);
  EXPECT_GT(t.reported, 1000);
  EXPECT_GT(t.dropped, 2000);
}

}  // namespace
}  // namespace kessler
