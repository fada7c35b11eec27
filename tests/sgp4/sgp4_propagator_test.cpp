// Sgp4Propagator: scenario time to each object's own element epoch, TEME states in m and m/s (checked
// against the reference output tcppver.out), lookup by id after removals, thread-count independence.
#include <gtest/gtest.h>
#include <omp.h>

#include <string>

#include "core/catalog/bundled_datasets.hpp"
#include "core/catalog/tle.hpp"
#include "core/sgp4/sgp4_propagator.hpp"

namespace kessler {
namespace {

MeanElements parse(const char* l1, const char* l2) {
  ParseProblem p;
  auto el = parse_tle_lines(l1, l2, {}, &p);
  EXPECT_TRUE(el) << p.message;
  return *el;
}

TEST(Sgp4Propagator, StatesFollowEachObjectsEpochAndSurviveRemovals) {
  // Two sets of the verification file: 00005 (its epoch is the scenario epoch) and 06251.
  const MeanElements a = parse("1 00005U 58002B   00179.78495062  .00000023  00000-0  28098-4 0  4753",
                               "2 00005  34.2682 348.7242 1859667 331.7664  19.3264 10.82419157413667");
  const MeanElements b = parse("1 06251U 62025E   06176.82412014  .00008885  00000-0  12808-3 0  3985",
                               "2 06251  58.0579  54.0425 0030035 139.1568 221.1854 15.56387291  6774");
  Sgp4Propagator propagator({5, 6251}, {a, b}, a.epoch);
  Population population;
  population.add({5, "A", {}, {}, 1.0, 1.0, 0.0, 0.0, ObjectStatus::kPassive});
  population.add({6251, "B", {}, {}, 1.0, 1.0, 0.0, 0.0, ObjectStatus::kPassive});
  propagator.step(population, 0.0, 21600.0);  // to 360 min
  // tcppver.out, set 5 at 360 min: -7154.03120202 -3783.17682504 -3536.19412294 km,
  // 4.741887409 -4.151817765 -2.093935425 km/s.
  EXPECT_NEAR(population.state.x[0], -7154031.20202, 1e-3);
  EXPECT_NEAR(population.state.y[0], -3783176.82504, 1e-3);
  EXPECT_NEAR(population.state.z[0], -3536194.12294, 1e-3);
  EXPECT_NEAR(population.state.vx[0], 4741.887409, 1e-5);
  EXPECT_NEAR(population.state.vy[0], -4151.817765, 1e-5);
  EXPECT_NEAR(population.state.vz[0], -2093.935425, 1e-5);

  // Object B at scenario time t is at its own tsince = t + (epoch_a - epoch_b).
  const Sgp4Record rb = sgp4_initialise(b);
  const double tsince_b = (21600.0 + a.epoch.seconds_since(b.epoch)) / 60.0;
  const Sgp4State sb = sgp4_propagate(rb, tsince_b);
  EXPECT_NEAR(population.state.x[1], sb.position_km[0] * 1000.0, 1e-3);

  // Remove A: B keeps its element set.
  population.remove_flagged({1, 0});
  propagator.step(population, 21600.0, 60.0);
  ASSERT_EQ(population.size(), 1u);
  const Sgp4State sb2 = sgp4_propagate(rb, tsince_b + 1.0);
  EXPECT_NEAR(population.state.x[0], sb2.position_km[0] * 1000.0, 1e-3);
  EXPECT_NEAR(population.state.vz[0], sb2.velocity_km_s[2] * 1000.0, 1e-6);

  // An object without an element set is an error naming it.
  population.add({42, "STRAY", {}, {}, 1.0, 1.0, 0.0, 0.0, ObjectStatus::kPassive});
  try {
    propagator.step(population, 21660.0, 60.0);
    FAIL() << "expected an exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("42"), std::string::npos);
  }
}

TEST(Sgp4Propagator, SameBitsWithOneOrFourThreads) {
  std::string error;
  auto input = load_bundled_catalog("catalog-2022", default_datasets_dir(), &error);
  ASSERT_TRUE(input) << error;
  const UtcEpoch start = UtcEpoch::from_calendar(2022, 1, 1, 0, 0, 0);
  const IngestResult ingest = ingest_catalog(*input, IngestRules{}, start, 1);
  auto run = [&](int threads) {
    omp_set_num_threads(threads);
    Population p = ingest.population;
    Sgp4Propagator prop(p.id, ingest.elements, start);
    for (int k = 0; k < 3; ++k) prop.step(p, 60.0 * k, 60.0);
    return p.state;
  };
  const StateArrays one = run(1), four = run(4);
  EXPECT_EQ(one.x, four.x);
  EXPECT_EQ(one.vz, four.vz);
  // And the propagator (vector path) agrees with the ingest's scalar SGP4 at t = 0 to rounding (1 mm).
  Population p = ingest.population;
  Sgp4Propagator prop(p.id, ingest.elements, start);
  prop.set_states(p, 0.0);
  for (std::size_t i = 0; i < p.size(); i += 97)
    ASSERT_NEAR(p.state.x[i], ingest.population.state.x[i], 1e-3);
}

}  // namespace
}  // namespace kessler
