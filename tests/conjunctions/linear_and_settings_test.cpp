// The paper's linear formula on its own three cases, the bad settings the detector refuses, and the
// catalog view of closest encounters.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "core/conjunctions/closest_encounters.hpp"
#include "core/conjunctions/detector.hpp"
#include "core/conjunctions/narrow_phase_linear.hpp"

namespace kessler {
namespace {

// The paper: tau_d from the start states, then d = |x1 - x2| for tau_d < 0, |x1 + tau_d v1 - x2 -
// tau_d v2| inside [0, dt], and |x1 + dt v1 - x2 - dt v2| beyond dt. Numbers chosen to be exact.
TEST(LinearFormula, ClosestApproachInsideTheStep) {
  // Relative position (-40, 3, 0) m, relative velocity (8, 0, 0) m/s: tau = 5 s, d = 3 m.
  const double x1[3] = {7e6 - 40.0, 3.0, 0.0}, v1[3] = {7000.0, 0.0, 0.0};
  const double x2[3] = {7e6, 0.0, 0.0}, v2[3] = {6992.0, 0.0, 0.0};
  const PairMinimum m = linear_closest_approach(x1, v1, x2, v2, 10.0);
  EXPECT_EQ(m.tau_s, 5.0);
  EXPECT_EQ(m.distance_m, 3.0);
}

TEST(LinearFormula, ApproachBeforeTheStepClampsToItsStart) {
  // Receding: tau_d = -5 s < 0, so d = |x1 - x2| = |(40, 3, 0)| (the paper's first case).
  const double x1[3] = {7e6 + 40.0, 3.0, 0.0}, v1[3] = {7000.0, 0.0, 0.0};
  const double x2[3] = {7e6, 0.0, 0.0}, v2[3] = {6992.0, 0.0, 0.0};
  const PairMinimum m = linear_closest_approach(x1, v1, x2, v2, 10.0);
  EXPECT_EQ(m.tau_s, 0.0);
  EXPECT_DOUBLE_EQ(m.distance_m, std::hypot(40.0, 3.0));
}

TEST(LinearFormula, ApproachAfterTheStepClampsToItsEnd) {
  // tau_d = 20 s > dt = 10 s: d = |x1 + dt v1 - x2 - dt v2| = |(-80, 4, 0) + 10 (4, 0, 0)| = |(-40, 4, 0)|.
  const double x1[3] = {7e6 - 80.0, 4.0, 0.0}, v1[3] = {7004.0, 0.0, 0.0};
  const double x2[3] = {7e6, 0.0, 0.0}, v2[3] = {7000.0, 0.0, 0.0};
  const PairMinimum m = linear_closest_approach(x1, v1, x2, v2, 10.0);
  EXPECT_EQ(m.tau_s, 10.0);
  EXPECT_DOUBLE_EQ(m.distance_m, std::hypot(40.0, 4.0));
}

TEST(LinearFormula, ReportsOnlyInTheStepWhereTheApproachTurns) {
  // Approaching at the start; at the end the true end states still approach: the next step reports.
  ObjectStep a{
      {7e6 - 80.0, 4.0, 0.0}, {7004.0, 0.0, 0.0}, {7e6 - 80.0 + 70040.0, 4.0, 0.0}, {7004.0, 0.0, 0.0}};
  ObjectStep b{{7e6, 0.0, 0.0}, {7000.0, 0.0, 0.0}, {7e6 + 70000.0, 0.0, 0.0}, {7000.0, 0.0, 0.0}};
  PairMinimum out[kMaxMinimaPerStep];
  EXPECT_EQ(linear_minimum(a, b, 10.0, 100.0, out), 0);
  // A step that starts receding reports nothing either (the minimum was in an earlier step).
  ObjectStep c{{7e6 + 40.0, 3.0, 0.0}, {7000.0, 0.0, 0.0}, {7e6 + 70040.0, 3.0, 0.0}, {7000.0, 0.0, 0.0}};
  ObjectStep d{{7e6, 0.0, 0.0}, {6992.0, 0.0, 0.0}, {7e6 + 69920.0, 0.0, 0.0}, {6992.0, 0.0, 0.0}};
  EXPECT_EQ(linear_minimum(c, d, 10.0, 100.0, out), 0);
  // The turn inside the step: reported with the paper's numbers.
  ObjectStep e{{7e6 - 40.0, 3.0, 0.0}, {7000.0, 0.0, 0.0}, {7e6 + 69960.0, 3.0, 0.0}, {7000.0, 0.0, 0.0}};
  ASSERT_EQ(linear_minimum(e, d, 10.0, 3.0, out), 1);
  EXPECT_EQ(out[0].tau_s, 5.0);
  EXPECT_EQ(out[0].distance_m, 3.0);
  EXPECT_EQ(linear_minimum(e, d, 10.0, 2.999, out), 0);
}

TEST(Settings, BadSettingsAreRefusedNamingTheField) {
  auto problem = [](ConjunctionSettings s, double dt) {
    auto p = ConjunctionDetector::validate(s, dt);
    return p ? *p : std::string();
  };
  ConjunctionSettings s;
  EXPECT_EQ(problem(s, 10.0), "");
  for (double kappa : {0.0, -1.0, 10.0001, double(NAN), double(INFINITY)}) {
    ConjunctionSettings bad = s;
    bad.kappa_max = kappa;
    EXPECT_EQ(problem(bad, 10.0).rfind("kappa_max", 0), 0u) << kappa;
    EXPECT_THROW(ConjunctionDetector{bad}, std::invalid_argument);
  }
  ConjunctionSettings edge = s;
  edge.kappa_max = 10.0;
  EXPECT_EQ(problem(edge, 10.0), "");
  for (double screen : {-1.0, double(NAN), double(INFINITY), 25000e3}) {
    ConjunctionSettings bad = s;
    bad.screening_distance_m = screen;
    EXPECT_EQ(problem(bad, 10.0).rfind("screening_distance_m", 0), 0u) << screen;
  }
  for (double dt : {0.0, -10.0, double(NAN), 2000.0}) EXPECT_EQ(problem(s, dt).rfind("dt_s", 0), 0u) << dt;
  EXPECT_EQ(problem(s, 600.0), "");
  // The scan refuses a bad step the same way.
  ConjunctionDetector detector(s);
  Population p;
  StateArrays a;
  std::vector<Encounter> out;
  EXPECT_THROW(detector.scan(p, StepEnds{0.0, 0.0, &a, &a}, out), std::invalid_argument);
  // A step is checked once, not every scan: a good one passes, and a bad one after it is still refused.
  EXPECT_NO_THROW(detector.scan(p, StepEnds{0.0, 10.0, &a, &a}, out));
  EXPECT_NO_THROW(detector.scan(p, StepEnds{10.0, 10.0, &a, &a}, out));
  for (double dt : {0.0, -10.0, double(NAN), 2000.0}) {
    try {
      detector.scan(p, StepEnds{20.0, dt, &a, &a}, out);
      ADD_FAILURE() << "dt " << dt << " accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_EQ(std::string(e.what()).rfind("dt_s", 0), 0u) << e.what();
    }
  }
  EXPECT_NO_THROW(detector.scan(p, StepEnds{20.0, 10.0, &a, &a}, out));
}

Encounter encounter(ObjectId a, ObjectId b, double t, double d) {
  Encounter e;
  e.id1 = a;
  e.id2 = b;
  e.tca_s = t;
  e.miss_distance_m = d;
  return e;
}

TEST(ClosestEncounters, KeepsTheClosestPerPairWhateverTheOrder) {
  std::vector<Encounter> stream = {encounter(1, 2, 10.0, 50.0), encounter(1, 2, 20.0, 30.0),
                                   encounter(1, 2, 30.0, 30.0), encounter(3, 4, 5.0, 80.0),
                                   encounter(1, 3, 40.0, 10.0), encounter(3, 4, 60.0, 90.0)};
  ClosestEncounterTable table;
  for (const auto& e : stream) table.update(e);
  ASSERT_EQ(table.size(), 3u);
  const auto entries = table.entries();
  ASSERT_EQ(entries.size(), 3u);
  // Canonical order (time, then ids); the tie at 30 m keeps the earlier encounter.
  EXPECT_EQ(entries[0].id1, 3u);
  EXPECT_EQ(entries[0].miss_distance_m, 80.0);
  EXPECT_EQ(entries[1].tca_s, 20.0);
  EXPECT_EQ(entries[2].id2, 3u);
  std::mt19937 rng(1);
  for (int round = 0; round < 20; ++round) {
    std::shuffle(stream.begin(), stream.end(), rng);
    ClosestEncounterTable shuffled;
    for (const auto& e : stream) shuffled.update(e);
    const auto again = shuffled.entries();
    ASSERT_EQ(again.size(), entries.size());
    for (std::size_t k = 0; k < again.size(); ++k) {
      EXPECT_EQ(again[k].tca_s, entries[k].tca_s);
      EXPECT_EQ(again[k].miss_distance_m, entries[k].miss_distance_m);
    }
    // A table restored from entries() (a checkpoint) is the same table.
    ClosestEncounterTable restored;
    for (const auto& e : again) restored.update(e);
    EXPECT_EQ(restored.entries().size(), entries.size());
  }
}

}  // namespace
}  // namespace kessler
