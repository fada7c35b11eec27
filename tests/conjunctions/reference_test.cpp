// The detector against the brute-force reference on random LEO populations, and its independence of
// the thread count.
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <cstring>
#include <iostream>
#include <map>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "tests/conjunctions/brute_force_reference.hpp"
#include "tests/conjunctions/scenario.hpp"

namespace kessler {
namespace {

constexpr double kDt = 10.0;
constexpr int kSteps = 200;
constexpr std::size_t kObjects = 2000;

struct RandomLeo {
  Population population;
  std::vector<StateArrays> snaps;
};

// 2,000 objects between 500 and 700 km altitude, every fifth active, 200 steps of 10 s.
const RandomLeo& random_leo(bool big_radii) {
  static std::map<bool, RandomLeo> cache;
  auto it = cache.find(big_radii);
  if (it != cache.end()) return it->second;
  RandomLeo& r = cache[big_radii];
  const auto states = testing::random_leo_states(kObjects, big_radii ? 7 : 11, 500e3, 700e3);
  std::mt19937_64 rng(big_radii ? 3 : 5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<double> radii;
  std::vector<ObjectStatus> statuses;
  std::vector<ObjectId> ids;
  for (std::size_t k = 0; k < kObjects; ++k) {
    radii.push_back(big_radii ? 600.0 + 1400.0 * u(rng) : 0.05 + 3.0 * u(rng));
    statuses.push_back(k % 5 == 0 ? ObjectStatus::kActive : ObjectStatus::kPassive);
    ids.push_back(100000 - 37 * k);  // ids fall as indices rise: "lower id first" is exercised
  }
  r.population = testing::population_from_states(states, radii, statuses, ids);
  r.snaps = testing::kepler_snapshots(states, kDt, kSteps);
  return r;
}

double radius_of(const Population& p, ObjectId id) {
  return p.radius_m[*p.index_of(id)];
}

void expect_matches_reference(const RandomLeo& scenario, const ConjunctionSettings& settings) {
  const auto events = testing::run_detector(scenario.population, scenario.snaps, kDt, settings);
  const testing::BruteForceReference reference(scenario.population, scenario.snaps, kDt);
  const auto expected = reference.run(settings, 100);
  std::cout << "  detector " << events.size() << " events, reference " << expected.size() << "\n";
  EXPECT_GE(expected.size(), 200u) << "the scenario should give hundreds of events";

  // Match by pair and time; minima within 1e-6 m of the threshold may fall either side of it.
  std::vector<bool> used(events.size(), false);
  std::size_t matched = 0, borderline = 0;
  for (const auto& ref : expected) {
    bool found = false;
    for (std::size_t k = 0; k < events.size(); ++k) {
      const Encounter& e = events[k];
      if (used[k] || e.id1 != ref.id1 || e.id2 != ref.id2 || std::fabs(e.tca_s - ref.tca_s) > 1e-3) continue;
      used[k] = found = true;
      EXPECT_NEAR(e.miss_distance_m, ref.distance_m, 0.01)
          << ref.id1 << "-" << ref.id2 << " at " << ref.tca_s;
      ++matched;
      break;
    }
    if (!found) {
      if (std::fabs(ref.distance_m - ref.threshold_m) < 1e-6) {
        ++borderline;
        continue;
      }
      ADD_FAILURE() << "missed: " << ref.id1 << "-" << ref.id2 << " at " << ref.tca_s << " s, "
                    << ref.distance_m << " m (threshold " << ref.threshold_m << ")";
    }
  }
  for (std::size_t k = 0; k < events.size(); ++k) {
    if (used[k]) continue;
    const Encounter& e = events[k];
    const double h = settings.screening_distance_m > 0.0
                         ? settings.screening_distance_m
                         : settings.kappa_max * (radius_of(scenario.population, e.id1) +
                                                 radius_of(scenario.population, e.id2));
    if (std::fabs(e.miss_distance_m - h) < 1e-6) continue;
    ADD_FAILURE() << "extra: " << e.id1 << "-" << e.id2 << " at " << e.tca_s << " s, " << e.miss_distance_m
                  << " m";
  }
  EXPECT_EQ(matched + borderline, expected.size());
  // Canonical order.
  for (std::size_t k = 1; k < events.size(); ++k) EXPECT_FALSE(canonical_less(events[k], events[k - 1]));
}

TEST(Reference, ScreeningDistanceFindsEveryMinimumAndNothingElse) {
  ConjunctionSettings s;
  s.screening_distance_m = 20e3;
  expect_matches_reference(random_leo(false), s);
}

TEST(Reference, InflatedKappaFindsEveryMinimumAndNothingElse) {
  ConjunctionSettings s;
  s.kappa_max = 10.0;
  expect_matches_reference(random_leo(true), s);
}

bool bitwise_equal(const Encounter& a, const Encounter& b) {
  auto same = [](double x, double y) { return std::memcmp(&x, &y, sizeof x) == 0; };
  bool eq = a.id1 == b.id1 && a.id2 == b.id2 && a.kind == b.kind && same(a.tca_s, b.tca_s) &&
            same(a.miss_distance_m, b.miss_distance_m) && same(a.relative_speed_m_s, b.relative_speed_m_s) &&
            same(a.kappa, b.kappa);
  for (int c = 0; c < 3; ++c)
    eq = eq && same(a.r1_m[c], b.r1_m[c]) && same(a.v1_m_s[c], b.v1_m_s[c]) && same(a.r2_m[c], b.r2_m[c]) &&
         same(a.v2_m_s[c], b.v2_m_s[c]);
  return eq;
}

TEST(Reference, BitwiseIdenticalForOneTwoAndFourThreads) {
  const RandomLeo& scenario = random_leo(false);
  for (NarrowPhase phase : {NarrowPhase::kHermite, NarrowPhase::kLinear}) {
    ConjunctionSettings s;
    s.screening_distance_m = 20e3;
    s.narrow_phase = phase;
    const int saved = omp_get_max_threads();
    std::vector<std::vector<Encounter>> runs;
    for (int threads : {1, 2, 4}) {
      omp_set_num_threads(threads);
      runs.push_back(testing::run_detector(scenario.population, scenario.snaps, kDt, s));
    }
    omp_set_num_threads(saved);
    ASSERT_GT(runs[0].size(), 100u);
    for (std::size_t r = 1; r < runs.size(); ++r) {
      ASSERT_EQ(runs[r].size(), runs[0].size());
      for (std::size_t k = 0; k < runs[0].size(); ++k)
        ASSERT_TRUE(bitwise_equal(runs[r][k], runs[0][k])) << k;
    }
  }
}

// The propagator shares objects out in chunks of equal cost (thread_chunks.hpp, ChunkLayout), and the
// grid's box pass takes the same chunks: chunks far from equal in size must give the same events.
TEST(Reference, UnequalChunksGiveTheSameEvents) {
  const RandomLeo& scenario = random_leo(false);
  const std::vector<StateArrays> first(scenario.snaps.begin(), scenario.snaps.begin() + 31);
  ConjunctionSettings s;
  s.screening_distance_m = 20e3;
  const std::size_t n = scenario.population.size();
  std::vector<std::size_t> costly;  // the first 40 % of the objects, each costing 6 ordinary ones
  for (std::size_t i = 0; i < 2 * n / 5; ++i) costly.push_back(i);
  const int saved = omp_get_max_threads();
  omp_set_num_threads(1);
  const auto one = testing::run_detector(scenario.population, first, kDt, s);
  for (int threads : {2, 3}) {
    ChunkLayout uneven;
    uneven.weighted(n, static_cast<std::size_t>(threads), costly, 5.0);
    ASSERT_LT(uneven.chunk(0).end - uneven.chunk(0).begin, n / (2 * static_cast<std::size_t>(threads)));
    omp_set_num_threads(threads);
    const auto events = testing::run_detector(scenario.population, first, kDt, s, nullptr, &uneven);
    ASSERT_GT(one.size(), 20u);
    ASSERT_EQ(events.size(), one.size()) << threads << " threads";
    for (std::size_t k = 0; k < one.size(); ++k)
      ASSERT_TRUE(bitwise_equal(events[k], one[k])) << threads << " threads: " << k;
  }
  omp_set_num_threads(saved);
}

// The shared scans' case: the random LEO scenario's first 40 steps, screened at 20 km.
struct FirstSteps {
  const RandomLeo& scenario = random_leo(false);
  std::vector<StateArrays> states{scenario.snaps.begin(), scenario.snaps.begin() + 41};
  ConjunctionSettings settings = [] {
    ConjunctionSettings s;
    s.screening_distance_m = 20e3;
    return s;
  }();
  std::size_t steps() const { return states.size() - 1; }
  StepEnds step(std::size_t k) const {
    return {static_cast<double>(k) * kDt, kDt, &states[k], &states[k + 1]};
  }
};

// The parts' encounters together, in canonical order, are bitwise the whole scan's.
void expect_whole_scan(std::vector<Encounter> together, const std::vector<Encounter>& whole,
                       const std::string& what) {
  std::sort(together.begin(), together.end(), canonical_less);
  ASSERT_EQ(together.size(), whole.size()) << what;
  for (std::size_t k = 0; k < whole.size(); ++k)
    ASSERT_TRUE(bitwise_equal(together[k], whole[k])) << what << ": " << k;
}

// A scan shared out in parts (ConjunctionDetector::set_share, as the MPI ranks of core/distributed/ share
// it): the parts' encounters together, in canonical order, are bitwise the whole scan's, each found once,
// with one thread per part and with teams of 2, 3 and 4 threads (whose grids have several regions, whose
// borders the parts must place alike); with parts x threads above the grid's 16 regions, and with more
// parts than regions (several parts share a region's slots).
TEST(Reference, SharedScanPartsTogetherGiveTheWholeScan) {
  const FirstSteps first;
  const int saved = omp_get_max_threads();
  omp_set_num_threads(2);
  const auto whole = testing::run_detector(first.scenario.population, first.states, kDt, first.settings);
  ASSERT_GT(whole.size(), 20u);
  const std::pair<int, std::size_t> cases[] = {{1, 2}, {1, 3}, {1, 4}, {2, 2}, {2, 3},  {2, 4}, {3, 2},
                                               {3, 3}, {3, 4}, {4, 5}, {2, 9}, {1, 20}, {2, 23}};
  for (const auto& [threads, parts] : cases) {
    omp_set_num_threads(threads);
    std::vector<Encounter> together;
    std::size_t parts_with_pairs = 0;
    for (std::size_t part = 0; part < parts; ++part) {
      ConjunctionDetector detector(first.settings);
      detector.set_share(part, parts);
      std::size_t pairs = 0;
      for (std::size_t k = 0; k < first.steps(); ++k) {
        detector.scan(first.scenario.population, first.step(k), together);
        pairs += detector.last_candidate_pairs();
      }
      parts_with_pairs += pairs > 0 ? 1 : 0;
    }
    const std::string what = std::to_string(parts) + " parts of " + std::to_string(threads) + " threads";
    EXPECT_EQ(parts_with_pairs, parts) << what << ": each walks a share";
    expect_whole_scan(together, whole, what);
  }
  omp_set_num_threads(saved);
  ConjunctionDetector detector(first.settings);
  EXPECT_THROW(detector.set_share(2, 2), std::invalid_argument);
  EXPECT_THROW(detector.set_share(0, 0), std::invalid_argument);
}

// The parts of a shared scan in step, as MPI ranks run them: after each step every part is told all
// parts' occupied cells (each part sorts only its own regions' cells), so their cells coarsen alike, and
// exactly as those of one detector whose grid has the same regions (no region's cells counted twice, also
// where several parts share a region). The encounters together are still the whole scan's, and parts
// that are told nothing keep finer cells (they never coarsen).
TEST(Reference, SharedScanPartsCoarsenTheirCellsAlike) {
  const FirstSteps first;
  const Population& population = first.scenario.population;
  const int saved = omp_get_max_threads();
  for (const auto& [threads, parts] : {std::pair<int, std::size_t>{2, 3}, {1, 20}}) {
    omp_set_num_threads(threads);
    const std::size_t regions = std::min<std::size_t>(parts * static_cast<std::size_t>(threads), 16);
    ConjunctionDetector one(first.settings, GridSettings{regions});
    std::vector<ConjunctionDetector> told, untold;
    for (std::size_t part = 0; part < parts; ++part) {
      told.emplace_back(first.settings);
      told.back().set_share(part, parts);
      untold.emplace_back(first.settings);
      untold.back().set_share(part, parts);
    }
    std::vector<Encounter> whole, together, ignored;
    for (std::size_t k = 0; k < first.steps(); ++k) {
      one.scan(population, first.step(k), whole);
      std::size_t occupied = 0;
      for (std::size_t part = 0; part < parts; ++part) {
        told[part].scan(population, first.step(k), together);
        untold[part].scan(population, first.step(k), ignored);
        occupied += told[part].sorted_occupied_cells();
        ASSERT_EQ(told[part].grid().cell_size_m(), one.grid().cell_size_m()) << parts << " parts, step " << k;
        ASSERT_EQ(told[part].grid().slot_count(), one.grid().slot_count()) << parts << " parts, step " << k;
      }
      for (ConjunctionDetector& detector : told) detector.set_all_parts_occupied(occupied);
    }
    EXPECT_GT(told[0].grid().cell_size_m(), 1.5 * untold[0].grid().cell_size_m())
        << parts << " parts: a sparse population's cells should coarsen";
    expect_whole_scan(together, whole, std::to_string(parts) + " parts");
  }
  omp_set_num_threads(saved);
}

TEST(Reference, SixteenAndTwentyThreadsMatchOneOnTheFirstSteps) {
  // 16 threads: a region of space each; 20: more threads than regions, so some regions are sorted by
  // two threads, and each region's walk waits for both (there is no barrier after the sort).
  const RandomLeo& scenario = random_leo(false);
  const std::vector<StateArrays> first(scenario.snaps.begin(), scenario.snaps.begin() + 31);
  ConjunctionSettings s;
  s.screening_distance_m = 20e3;
  const int saved = omp_get_max_threads();
  omp_set_num_threads(1);
  const auto one = testing::run_detector(scenario.population, first, kDt, s);
  omp_set_num_threads(16);
  const auto sixteen = testing::run_detector(scenario.population, first, kDt, s);
  omp_set_num_threads(20);
  const auto twenty = testing::run_detector(scenario.population, first, kDt, s);
  omp_set_num_threads(saved);
  ASSERT_GT(one.size(), 20u);
  ASSERT_EQ(sixteen.size(), one.size());
  ASSERT_EQ(twenty.size(), one.size());
  for (std::size_t k = 0; k < one.size(); ++k) {
    ASSERT_TRUE(bitwise_equal(sixteen[k], one[k])) << "16 threads: " << k;
    ASSERT_TRUE(bitwise_equal(twenty[k], one[k])) << "20 threads: " << k;
  }
}

}  // namespace
}  // namespace kessler
