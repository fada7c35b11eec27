// Hand-made encounters with known answers: circular orbits whose closest approach follows from geometry,
// and straight-line motions whose numbers are exact in floating point.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "core/conjunctions/detector.hpp"
#include "tests/conjunctions/scenario.hpp"

namespace kessler {
namespace {

using testing::KeplerState;

constexpr double kMu = constants::kEarthMu_m3_s2;
const double kRadius = constants::kEarthEquatorialRadius_m + 700e3;

// A circular orbit of radius r in the plane spanned by unit vectors e1, e2 (motion from e1 towards
// e2), at angle theta (from e1) at t = 0.
KeplerState circular(double r, const Eigen::Vector3d& e1, const Eigen::Vector3d& e2, double theta) {
  const double v = std::sqrt(kMu / r);
  return KeplerState{r * (std::cos(theta) * e1 + std::sin(theta) * e2),
                     v * (-std::sin(theta) * e1 + std::cos(theta) * e2)};
}
double rate(double r) {
  return std::sqrt(kMu / (r * r * r));
}

ConjunctionSettings screening(double km) {
  ConjunctionSettings s;
  s.screening_distance_m = km * 1e3;
  return s;
}

const Eigen::Vector3d X = Eigen::Vector3d::UnitX(), Y = Eigen::Vector3d::UnitY(),
                      Z = Eigen::Vector3d::UnitZ();

TEST(HandMade, HeadOnMeetsAtTheGeometricPoint) {
  // Prograde and retrograde equatorial orbits 60 m apart in radius, both on the x axis at t_c.
  const double tc = 123.4, r1 = kRadius, r2 = kRadius + 60.0;
  const std::vector<KeplerState> objects = {circular(r1, X, Y, -rate(r1) * tc),
                                            circular(r2, X, -Y, -rate(r2) * tc)};
  const auto pop = testing::simple_population(objects, 5.0);  // kappa 10: threshold 100 m
  const auto snaps = testing::kepler_snapshots(objects, 10.0, 30);
  const auto events = testing::run_detector(pop, snaps, 10.0, ConjunctionSettings{});
  ASSERT_EQ(events.size(), 1u);
  EXPECT_NEAR(events[0].tca_s, tc, 1e-3);
  EXPECT_NEAR(events[0].miss_distance_m, 60.0, 0.01);
  EXPECT_NEAR(events[0].relative_speed_m_s, std::sqrt(kMu / r1) + std::sqrt(kMu / r2), 0.5);
  EXPECT_NEAR(events[0].kappa, 6.0, 1e-3);
  EXPECT_EQ(events[0].kind, EncounterKind::kConjunction);
  EXPECT_EQ(events[0].id1, 1u);
  EXPECT_EQ(events[0].id2, 2u);
  EXPECT_NEAR((events[0].r1_m - r1 * X).norm(), 0.0, 0.01);
  EXPECT_NEAR((events[0].r2_m - r2 * X).norm(), 0.0, 0.01);
}

TEST(HandMade, OvertakingInTheSamePlane) {
  // The inner orbit is faster and passes the outer one 1 km below it: the distance is exactly 1 km when
  // both are at the same angle, at t_c. The minimum is very flat (relative speed ~0.5 m/s).
  const double tc = 431.0, r1 = kRadius, r2 = kRadius + 1000.0;
  const std::vector<KeplerState> objects = {circular(r1, X, Y, -rate(r1) * tc),
                                            circular(r2, X, Y, -rate(r2) * tc)};
  const auto pop = testing::simple_population(objects, 1.0);
  const auto snaps = testing::kepler_snapshots(objects, 10.0, 90);
  const auto events = testing::run_detector(pop, snaps, 10.0, screening(5.0));
  ASSERT_EQ(events.size(), 1u);
  EXPECT_NEAR(events[0].tca_s, tc, 0.5);
  EXPECT_NEAR(events[0].miss_distance_m, 1000.0, 0.01);
  EXPECT_LT(events[0].relative_speed_m_s, 1.0);
}

// The separation rule (Population::separation_group): a real approach between two objects of the same
// non-zero group is not reported; in different groups, or with one in none, it is. Six objects cross
// in pairs far apart from each other, each pair with its own groups.
TEST(HandMade, ASharedSeparationGroupHidesThePairAndNothingElse) {
  const double tc = 55.5, r1 = kRadius, r2 = kRadius + 80.0;
  std::vector<KeplerState> objects;
  for (double theta : {0.0, 2.0, 4.0}) {
    const Eigen::Vector3d e1 = std::cos(theta) * X + std::sin(theta) * Y,
                          e2 = -std::sin(theta) * X + std::cos(theta) * Y;
    objects.push_back(circular(r1, e1, e2, -rate(r1) * tc));
    objects.push_back(circular(r2, e1, Z, -rate(r2) * tc));
  }
  auto pop = testing::simple_population(objects, 5.0);
  pop.separation_group = {3, 3, 3, 4, 0, 3};  // the first pair shares a group; the others do not
  const auto events = testing::run_detector(pop, testing::kepler_snapshots(objects, 10.0, 12), 10.0, {});
  ASSERT_EQ(events.size(), 2u);
  EXPECT_EQ(std::min(events[0].id1, events[1].id1), 3u);
  EXPECT_EQ(std::max(events[0].id1, events[1].id1), 5u);
  pop.separation_group.assign(6, 0);
  EXPECT_EQ(testing::run_detector(pop, testing::kepler_snapshots(objects, 10.0, 12), 10.0, {}).size(), 3u);
}

// Collision avoidance below full efficiency: 40 active objects each crossing a trackable passive one,
// far apart. At efficiency 1 every approach is an evasion (the paper), at 0 none is, at 0.5 about half
// (a keyed draw per approach: the same on every call).
TEST(HandMade, EvasionEfficiencyDecidesPerApproach) {
  const double tc = 55.5, r1 = kRadius, r2 = kRadius + 8.0;
  std::vector<KeplerState> objects;
  constexpr int kPairs = 40;
  for (int k = 0; k < kPairs; ++k) {
    const double theta = 2.0 * 3.14159265358979 * k / kPairs;
    const Eigen::Vector3d e1 = std::cos(theta) * X + std::sin(theta) * Y,
                          e2 = -std::sin(theta) * X + std::cos(theta) * Y;
    objects.push_back(circular(r1, e1, e2, -rate(r1) * tc));
    objects.push_back(circular(r2, e1, Z, -rate(r2) * tc));
  }
  auto pop = testing::simple_population(objects, 5.0);
  for (std::size_t i = 0; i < pop.size(); i += 2) pop.status[i] = ObjectStatus::kActive;
  const auto snaps = testing::kepler_snapshots(objects, 10.0, 12);
  auto count = [&](double efficiency, std::uint64_t seed) {
    ConjunctionSettings s;
    s.active_passive_evasion_efficiency = efficiency;
    s.seed = seed;
    int evasions = 0, collisions = 0;
    const auto events = testing::run_detector(pop, snaps, 10.0, s);
    EXPECT_EQ(events.size(), static_cast<std::size_t>(kPairs));
    for (const Encounter& e : events) {
      evasions += e.kind == EncounterKind::kEvasion;
      collisions += e.kind == EncounterKind::kCollision;
    }
    return std::pair{evasions, collisions};
  };
  EXPECT_EQ(count(1.0, 1).first, kPairs);
  const auto none = count(0.0, 1);
  EXPECT_EQ(none.first, 0);
  EXPECT_EQ(none.second, kPairs);  // 8 m apart, radii 5 + 5 m: not evaded, they hit
  const int half = count(0.5, 1).first;
  EXPECT_NEAR(half, kPairs / 2, 3.0 * std::sqrt(kPairs * 0.25));
  EXPECT_EQ(count(0.5, 1).first, half);
  int differ = 0;
  for (std::uint64_t seed = 2; seed < 6; ++seed) differ += count(0.5, seed).first != half;
  EXPECT_GT(differ, 0);
  ConjunctionSettings bad;
  bad.active_passive_evasion_efficiency = 1.5;
  EXPECT_THROW(ConjunctionDetector{bad}, std::invalid_argument);
}

TEST(HandMade, CrossingAtRightAngles) {
  // Equatorial and polar orbits 80 m apart in radius, both over the x axis at t_c.
  const double tc = 55.5, r1 = kRadius, r2 = kRadius + 80.0;
  const std::vector<KeplerState> objects = {circular(r1, X, Y, -rate(r1) * tc),
                                            circular(r2, X, Z, -rate(r2) * tc)};
  const auto pop = testing::simple_population(objects, 5.0);
  const auto events = testing::run_detector(pop, testing::kepler_snapshots(objects, 10.0, 12), 10.0, {});
  ASSERT_EQ(events.size(), 1u);
  EXPECT_NEAR(events[0].tca_s, tc, 1e-3);
  EXPECT_NEAR(events[0].miss_distance_m, 80.0, 0.01);
  EXPECT_NEAR(events[0].relative_speed_m_s, std::hypot(std::sqrt(kMu / r1), std::sqrt(kMu / r2)), 0.5);
}

TEST(HandMade, CollisionIsAConjunctionWithinTheRadii) {
  const double tc = 71.25, r1 = kRadius, r2 = kRadius + 0.5;
  const std::vector<KeplerState> objects = {circular(r1, X, Y, -rate(r1) * tc),
                                            circular(r2, X, -Y, -rate(r2) * tc)};
  const auto pop = testing::simple_population(objects, 1.0);
  const auto events = testing::run_detector(pop, testing::kepler_snapshots(objects, 10.0, 10), 10.0, {});
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].kind, EncounterKind::kCollision);
  EXPECT_NEAR(events[0].miss_distance_m, 0.5, 0.01);
  EXPECT_NEAR(events[0].kappa, 0.25, 0.005);
}

// Straight-line motion, exact in floating point: object 1 at x = 7e6 moving +y, object 2 at
// x = 7e6 + offset moving -y, meeting at tau_meet.
struct LineCase {
  Population population;
  std::vector<StateArrays> snaps;
};
LineCase lines(double offset_m, double t_meet_s, double dt_s, int steps, double r1, double r2) {
  LineCase c;
  const double speed = 140.0;
  std::vector<KeplerState> objects = {
      {Eigen::Vector3d(7e6, -speed * t_meet_s, 0.0), Eigen::Vector3d(0, speed, 0)},
      {Eigen::Vector3d(7e6 + offset_m, speed * t_meet_s, 0.0), Eigen::Vector3d(0, -speed, 0)}};
  c.population = testing::population_from_states(objects, {r1, r2},
                                                 {ObjectStatus::kPassive, ObjectStatus::kPassive}, {11, 4});
  for (int k = 0; k <= steps; ++k) {
    StateArrays s;
    s.resize(2);
    const double t = k * dt_s;
    s.set(0, objects[0].r_m + t * objects[0].v_m_s, objects[0].v_m_s);
    s.set(1, objects[1].r_m + t * objects[1].v_m_s, objects[1].v_m_s);
    c.snaps.push_back(s);
  }
  return c;
}

TEST(HandMade, GrazingExactlyAtTheThresholdCounts) {
  ConjunctionSettings s;
  s.kappa_max = 2.0;  // threshold 2 * (0.5 + 1.0) = 3 m
  for (NarrowPhase phase : {NarrowPhase::kHermite, NarrowPhase::kLinear}) {
    s.narrow_phase = phase;
    const LineCase at = lines(3.0, 5.0, 10.0, 2, 0.5, 1.0);
    const auto events = testing::run_detector(at.population, at.snaps, 10.0, s);
    ASSERT_EQ(events.size(), 1u);
    EXPECT_EQ(events[0].miss_distance_m, 3.0);
    EXPECT_EQ(events[0].kappa, 2.0);
    EXPECT_EQ(events[0].tca_s, 5.0);
    EXPECT_EQ(events[0].id1, 4u);  // lower id first, whatever the population order
    EXPECT_EQ(events[0].id2, 11u);
    const LineCase beyond = lines(3.0 + 1e-6, 5.0, 10.0, 2, 0.5, 1.0);
    EXPECT_TRUE(testing::run_detector(beyond.population, beyond.snaps, 10.0, s).empty());
  }
}

TEST(HandMade, ClosestApproachExactlyOnAStepBoundaryComesOnce) {
  ConjunctionSettings s;
  s.kappa_max = 2.0;
  for (NarrowPhase phase : {NarrowPhase::kHermite, NarrowPhase::kLinear}) {
    s.narrow_phase = phase;
    const LineCase c = lines(2.0, 20.0, 10.0, 5, 0.5, 1.0);
    const auto events = testing::run_detector(c.population, c.snaps, 10.0, s);
    ASSERT_EQ(events.size(), 1u);
    EXPECT_EQ(events[0].tca_s, 20.0);
    EXPECT_EQ(events[0].miss_distance_m, 2.0);
  }
  // The same on curved orbits, at and a hair's breadth around a boundary: once each time.
  for (double tc : {20.0, 20.0 - 1e-7, 20.0 + 1e-7, 30.0 - 1e-4, 30.0 + 1e-4}) {
    const double r1 = kRadius, r2 = kRadius + 30.0;
    const std::vector<KeplerState> objects = {circular(r1, X, Y, -rate(r1) * tc),
                                              circular(r2, X, -Y, -rate(r2) * tc)};
    const auto pop = testing::simple_population(objects, 5.0);
    const auto events = testing::run_detector(pop, testing::kepler_snapshots(objects, 10.0, 6), 10.0, {});
    ASSERT_EQ(events.size(), 1u) << "tc " << tc;
    EXPECT_NEAR(events[0].tca_s, tc, 1e-3);
    EXPECT_NEAR(events[0].miss_distance_m, 30.0, 0.01);
  }
}

TEST(HandMade, CoOrbitalPairStaysCloseAndEachMinimumComesOnce) {
  // Same circular radius, planes 1e-4 rad apart, phases 5e-5 rad apart: within ~0.8 km all the time,
  // closest at u = -du/2 + k pi (u: the first object's argument of latitude), where
  // cos(gamma) = cos(du) (1 + cos(di)) / 2 + (1 - cos(di)) / 2 and d = r sqrt(2 - 2 cos(gamma)).
  const double r = kRadius, di = 1e-4, du = 5e-5, u0 = 1.0;
  const Eigen::Vector3d tilted = std::cos(di) * Y + std::sin(di) * Z;
  const std::vector<KeplerState> objects = {circular(r, X, Y, u0), circular(r, X, tilted, u0 + du)};
  const auto pop = testing::simple_population(objects, 1.0);
  const int steps = 700;
  const double dt = 10.0, n = rate(r);
  std::size_t pairs = 0;
  const auto events =
      testing::run_detector(pop, testing::kepler_snapshots(objects, dt, steps), dt, screening(1.0), &pairs);
  EXPECT_EQ(pairs, static_cast<std::size_t>(steps));  // a candidate in every step
  const double cos_gamma = std::cos(du) * (1.0 + std::cos(di)) / 2.0 + (1.0 - std::cos(di)) / 2.0;
  const double d_min = r * std::sqrt(2.0 - 2.0 * cos_gamma);
  std::vector<double> expected;
  for (int k = 0; k < 10; ++k) {
    const double t = (-du / 2.0 + k * M_PI - u0) / n;
    if (t > 0.0 && t <= steps * dt) expected.push_back(t);
  }
  ASSERT_GE(expected.size(), 2u);
  ASSERT_EQ(events.size(), expected.size());
  for (std::size_t k = 0; k < expected.size(); ++k) {
    EXPECT_NEAR(events[k].tca_s, expected[k], 0.5);
    EXPECT_NEAR(events[k].miss_distance_m, d_min, 0.01);
  }
}

TEST(HandMade, ThePapersStatusRules) {
  const double tc = 35.0, r1 = kRadius, r2 = kRadius + 5.0;
  const std::vector<KeplerState> objects = {circular(r1, X, Y, -rate(r1) * tc),
                                            circular(r2, X, -Y, -rate(r2) * tc)};
  const auto snaps = testing::kepler_snapshots(objects, 10.0, 5);
  const auto A = ObjectStatus::kActive, P = ObjectStatus::kPassive;
  struct Case {
    ObjectStatus s1, s2;
    double radius2;
    bool evade;
    EncounterKind expected;
  };
  const Case cases[] = {
      {A, A, 1.0, true, EncounterKind::kEvasion},      {A, P, 1.0, true, EncounterKind::kEvasion},
      {A, P, 0.05, true, EncounterKind::kConjunction}, {P, A, 1.0, true, EncounterKind::kEvasion},
      {P, P, 1.0, true, EncounterKind::kConjunction},  {A, A, 1.0, false, EncounterKind::kConjunction},
      {P, P, 4.5, true, EncounterKind::kCollision},
  };
  for (const Case& c : cases) {
    const auto pop = testing::population_from_states(objects, {1.0, c.radius2}, {c.s1, c.s2}, {1, 2});
    ConjunctionSettings s = screening(0.1);
    s.active_pairs_evade = c.evade;
    const auto events = testing::run_detector(pop, snaps, 10.0, s);
    ASSERT_EQ(events.size(), 1u);
    EXPECT_EQ(events[0].kind, c.expected) << int(c.s1) << int(c.s2) << " " << c.radius2;
  }
}

}  // namespace
}  // namespace kessler

namespace kessler {
namespace {

TEST(HandMade, AbsurdObjectsNeitherBreakNorSlowTheGrid) {
  // The head-on pair plus an object moving at 80,000 km/s (a propagation gone wrong) and one with NaN
  // states: the pair's encounter is still found once; the absurd objects meet nothing.
  const double tc = 123.4, r1 = kRadius, r2 = kRadius + 60.0;
  std::vector<KeplerState> objects = {circular(r1, X, Y, -rate(r1) * tc),
                                      circular(r2, X, -Y, -rate(r2) * tc)};
  const auto pop2 = testing::simple_population(objects, 5.0);
  const auto snaps2 = testing::kepler_snapshots(objects, 10.0, 20);
  objects.push_back(KeplerState{Eigen::Vector3d(2e8, 0, 0), Eigen::Vector3d(8e7, 0, 0)});
  objects.push_back(KeplerState{Eigen::Vector3d(7e6, 1e3, 0), Eigen::Vector3d(0, 7.5e3, 0)});
  const auto pop = testing::simple_population(objects, 5.0);
  std::vector<StateArrays> snaps;
  for (std::size_t k = 0; k < snaps2.size(); ++k) {
    StateArrays s;
    s.resize(4);
    for (std::size_t i = 0; i < 2; ++i) s.set(i, snaps2[k].position(i), snaps2[k].velocity(i));
    s.set(2, objects[2].r_m + 10.0 * k * objects[2].v_m_s, objects[2].v_m_s);
    s.set(3, Eigen::Vector3d(NAN, 0, 0), Eigen::Vector3d(0, NAN, 0));
    snaps.push_back(s);
  }
  const auto events = testing::run_detector(pop, snaps, 10.0, ConjunctionSettings{});
  ASSERT_EQ(events.size(), 1u);
  EXPECT_NEAR(events[0].tca_s, tc, 1e-3);
  EXPECT_EQ(events[0].id2, 2u);
}

}  // namespace
}  // namespace kessler

namespace kessler {
namespace {

TEST(HandMade, FarOutPairMeetsThoughItsBoxesAreTooCoarseForTheGrid) {
  // Real catalogs hold objects far out (the paper's, some at ~10^12 m: elements that no longer describe
  // a near-Earth orbit). At 2 x 10^12 m rounding to floats widens each box by ~480 km a side, more than
  // any bound orbit sweeps in the step, so these objects are tested against every object instead of
  // through the grid (whose cell would otherwise grow to fit them): a head-on pair there (60 m apart in
  // radius) is found as surely as one in LEO, each once.
  const double tc = 123.4, tf = 77.7, r1 = kRadius, r2 = kRadius + 60.0, f1 = 2.0e12, f2 = 2.0e12 + 60.0;
  const std::vector<KeplerState> objects = {
      circular(r1, X, Y, -rate(r1) * tc), circular(f1, Y, Z, -rate(f1) * tf),
      circular(r2, X, -Y, -rate(r2) * tc), circular(f2, Y, -Z, -rate(f2) * tf)};
  const auto pop = testing::simple_population(objects, 5.0);  // kappa 10: threshold 100 m
  const auto events = testing::run_detector(pop, testing::kepler_snapshots(objects, 10.0, 20), 10.0, {});
  ASSERT_EQ(events.size(), 2u);
  EXPECT_EQ(events[0].id1, 2u);  // the far pair meets first
  EXPECT_EQ(events[0].id2, 4u);
  EXPECT_NEAR(events[0].tca_s, tf, 1e-3);
  EXPECT_NEAR(events[0].miss_distance_m, 60.0, 0.01);
  EXPECT_EQ(events[1].id1, 1u);
  EXPECT_EQ(events[1].id2, 3u);
  EXPECT_NEAR(events[1].tca_s, tc, 1e-3);
}

}  // namespace
}  // namespace kessler
