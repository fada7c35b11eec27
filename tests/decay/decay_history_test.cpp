// The whole decay chain held against the sky: the bundled catalog of 2019-03-19, its objects with apogee
// below 400 km (86 after the ingest), run through the core loop on observed solar activity for two months,
// against the SATCAT's decay dates (about 20 of them re-entered by 2019-05-18). With ballistic
// coefficients fitted in the run's atmosphere the run re-enters the same objects at about the same dates.
// Steps of 300 s with drag at their ends (the scenario has 120 s): fewer of the atmosphere's 120 s slots
// to evaluate, which is what a small population's run costs. The full check (13,556 objects, 22 months,
// the paper's BSTAR rule beside it, and the Iridium/Cosmos clouds) is `kessler-bench decay-history`
// (core/decay/README.md).
#include <gtest/gtest.h>

#include <cstdio>
#include <map>
#include <unordered_map>

#include "core/catalog/bundled_datasets.hpp"
#include "core/catalog/satcat.hpp"
#include "core/decay/reentry_history.hpp"
#include "core/scenario/run_builder.hpp"

namespace kessler {
namespace {

class BurnUps final : public NullSink {
 public:
  void on_burn_up(std::uint64_t, const BurnUp& b) override { time_s[b.id] = b.time_s; }
  std::map<ObjectId, double> time_s;
};

std::unordered_map<ObjectId, UtcEpoch> satcat_decays() {
  std::string why;
  const auto text =
      read_catalog_file(default_datasets_dir() + "/catalog/spacetrack_satcat_2021-01-19.csv.gz", &why);
  EXPECT_TRUE(text) << why;
  std::unordered_map<ObjectId, UtcEpoch> out;
  for (const auto& [id, e] : parse_satcat_csv(text ? *text : "", "satcat").entries)
    if (e.decay) out.emplace(id, *e.decay);
  return out;
}

ReentryComparison run_low_2019(v1::BallisticCoefficients rule) {
  v1::Scenario scenario;
  const auto error =
      load_scenario_file(default_datasets_dir() + "/../scenarios/decay-history-2019.yaml", scenario);
  EXPECT_FALSE(error) << error->message();
  scenario.set_end_epoch("2019-05-18T00:00:00Z");
  scenario.set_dt_s(300.0);
  scenario.mutable_population()->mutable_rules()->set_max_apogee_km(400.0);
  scenario.mutable_population()->set_ballistic_coefficients(rule);
  BuildOptions options;
  options.checkpoints = false;
  FieldError build_error;
  auto sim = build_simulation(scenario, options, &build_error);
  EXPECT_TRUE(sim) << build_error.message();
  if (!sim) return {};
  const std::vector<ObjectId> ids = sim->population().id;
  BurnUps burn_ups;
  RunControl control;
  sim->run(burn_ups, control);
  const SimulationConfig config = to_simulation_config(scenario);
  return compare_reentries(ids, burn_ups.time_s, satcat_decays(), config.start_epoch,
                           config.start_epoch.plus_seconds(config.duration_s));
}

TEST(DecayHistory, LowObjectsOf2019ReenterWhenTheSatcatSays) {
  const ReentryComparison c = run_low_2019(v1::BALLISTIC_COEFFICIENTS_FITTED);
  std::printf(
      "%lld objects, re-entered %lld (observed %lld), both %lld: recall %.2f, precision %.2f, median "
      "date error %.3f\n",
      static_cast<long long>(c.simulated), static_cast<long long>(c.predicted),
      static_cast<long long>(c.observed), static_cast<long long>(c.hits), c.recall, c.precision,
      c.median_date_error);
  EXPECT_GE(c.simulated, 80);
  EXPECT_GE(c.observed, 15);
  EXPECT_GE(c.recall, 0.7);
  EXPECT_GE(c.precision, 0.7);
  EXPECT_LE(c.median_date_error, 0.15);
}

TEST(ReentryHistory, CountsHitsMonthsAndDateErrors) {
  const UtcEpoch start = UtcEpoch::from_calendar(2020, 1, 1, 0, 0, 0.0);
  const UtcEpoch end = UtcEpoch::from_calendar(2020, 3, 1, 0, 0, 0.0);
  const double day = 86400.0;
  // 1: both (predicted day 40, observed day 50); 2: predicted only; 3: observed only; 4: neither;
  // 5: observed before the start (ignored); 6: predicted after the end.
  const std::map<ObjectId, double> burn_ups = {{1, 40 * day}, {2, 10 * day}, {6, 70 * day}};
  const std::unordered_map<ObjectId, UtcEpoch> decays = {{1, start.plus_seconds(50 * day)},
                                                         {3, start.plus_seconds(20 * day)},
                                                         {5, start.plus_seconds(-5 * day)}};
  const ReentryComparison c = compare_reentries({1, 2, 3, 4, 5, 6}, burn_ups, decays, start, end);
  EXPECT_EQ(c.simulated, 6);
  EXPECT_EQ(c.predicted, 2);
  EXPECT_EQ(c.observed, 2);
  EXPECT_EQ(c.hits, 1);
  EXPECT_DOUBLE_EQ(c.recall, 0.5);
  EXPECT_DOUBLE_EQ(c.precision, 0.5);
  EXPECT_DOUBLE_EQ(c.median_date_error, 0.2);
  ASSERT_EQ(c.by_month.size(), 3u);  // January, February, 1 March
  EXPECT_EQ(c.by_month[0].predicted, 1);
  EXPECT_EQ(c.by_month[0].observed, 1);
  EXPECT_EQ(c.by_month[1].predicted, 1);
  EXPECT_EQ(c.by_month[1].observed, 1);
  std::vector<std::optional<UtcEpoch>> removal = {
      std::nullopt, start.plus_seconds(-day), start.plus_seconds(10 * day), start.plus_seconds(100 * day)};
  EXPECT_DOUBLE_EQ(fraction_still_on_orbit(removal, start, end), 2.0 / 3.0);
}

}  // namespace
}  // namespace kessler
