// The scenario's `traffic` block: every refusal with its exact field path and reason, the mapping onto
// TrafficSettings (inline plan, shipped plans, business as usual, in that order), the run's key without
// traffic, and the shipped constellations scenario.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "core/scenario/run_builder.hpp"
#include "core/scenario/traffic_validation.hpp"
#include "tests/scenario/verdict_table.hpp"

namespace kessler {
namespace {

constexpr const char* kConstellations = KESSLER_SCENARIOS_DIR "/constellations-2022.yaml";
constexpr const char* kHeader = "label,epoch,epoch_end,count,altitude_km,inclination_deg,planes\n";

// A synthetic population over one day from 2022-01-01, with `traffic` as given.
std::string with_traffic(const std::string& traffic, const std::string& extra = "") {
  return "start_epoch: 2022-01-01T00:00:00Z\nduration_days: 1\npopulation: {synthetic: {objects: 10}}\n" +
         extra + "traffic:\n" + traffic;
}

// An inline plan (YAML block) of the given rows under kHeader.
std::string inline_plan(const std::string& rows) {
  std::string text = "  launch_plan_csv: |\n    " + std::string(kHeader);
  std::size_t start = 0;
  while (start < rows.size()) {
    const std::size_t end = rows.find('\n', start);
    text += "    " + rows.substr(start, end - start) + "\n";
    if (end == std::string::npos) break;
    start = end + 1;
  }
  return text;
}

const std::string kGoodRow = "a,2022-01-01T01:00:00Z,2022-01-01T03:00:00Z,10,550,53,2";

using Case = test::VerdictCase;

const Case kRefusals[] = {
    {"count zero", with_traffic(inline_plan(kGoodRow + "\nb,2022-01-01T02:00:00Z,,0,550,53,1")),
     "traffic.launch_plan_csv: line 3: count: must be a whole number >= 1"},
    {"unknown column", with_traffic("  launch_plan_csv: \"epoch,count,colour\\n\"\n"),
     "traffic.launch_plan_csv: line 1: colour: unknown column"},
    {"planes do not divide", with_traffic(inline_plan("a,2022-01-01T01:00:00Z,,10,550,53,3")),
     "traffic.launch_plan_csv: line 2: planes: must divide count"},
    {"too many objects", with_traffic(inline_plan("a,2022-01-01T01:00:00Z,,1000000000,550,53,1")),
     "traffic.launch_plan_csv: launches 1000000000 objects, more than 10000000"},
    {"unknown plan", with_traffic("  plans: [kuiper, foo]\n"),
     "traffic.plans[1]: no shipped plan 'foo' (expected one of: starlink-gen1, oneweb-phase1, kuiper)"},
    {"plan twice", with_traffic("  plans: [kuiper, starlink-gen1, kuiper]\n"),
     "traffic.plans[2]: is plans[0] again ('kuiper'); each plan launches its objects once"},
    {"probability above 1", with_traffic("  disposal: {success_probability: 1.5}\n"),
     "traffic.disposal.success_probability: must be in [0, 1], got 1.5"},
    {"probability negative", with_traffic("  disposal: {success_probability: -0.1}\n"),
     "traffic.disposal.success_probability: must be in [0, 1], got -0.1"},
    {"target lifetime zero", with_traffic("  disposal: {target_lifetime_years: 0}\n"),
     "traffic.disposal.target_lifetime_years: must be positive, got 0"},
    {"target lifetime negative", with_traffic("  disposal: {target_lifetime_years: -5}\n"),
     "traffic.disposal.target_lifetime_years: must be positive, got -5"},
    {"window zero", with_traffic("  business_as_usual: {enabled: true, window_years: 0}\n"),
     "traffic.business_as_usual.window_years: must be positive, got 0"},
    {"window negative", with_traffic("  business_as_usual: {window_years: -8}\n"),
     "traffic.business_as_usual.window_years: must be positive, got -8"},
    {"window end unparseable", with_traffic("  business_as_usual: {enabled: true, window_end: soon}\n"),
     "traffic.business_as_usual.window_end: "},  // the reason is UtcEpoch's; the path is what matters here
    {"sgp4", with_traffic("  enabled: true\n  plans: [kuiper]\n", "propagator: sgp4\n"),
     "traffic.enabled: traffic needs the numerical propagator (SGP4 cannot move launched objects, which "
     "have no element sets); set propagator: numerical or leave it out"},
    {"no launches", with_traffic("  enabled: true\n  disposal: {deorbit: true}\n"),
     "traffic.enabled: nothing to do: give launch_plan_csv, plans, business_as_usual (enabled: true) or "
     "catalog_active_lifetime_years"},
    {"catalog lifetime", with_traffic("  enabled: true\n  catalog_active_lifetime_years: -1\n"),
     "traffic.catalog_active_lifetime_years: must be in [0, 100] years, got -1"},
    {"business as usual off is no source",
     with_traffic("  enabled: true\n  business_as_usual: {window_years: 4}\n"),
     "traffic.enabled: nothing to do: give launch_plan_csv, plans, business_as_usual (enabled: true) or "
     "catalog_active_lifetime_years"},
};

class TrafficRefusals : public ::testing::TestWithParam<Case> {};

TEST_P(TrafficRefusals, NameTheFieldAndTheReason) {
  test::expect_verdict(GetParam());
}

INSTANTIATE_TEST_SUITE_P(Table, TrafficRefusals, ::testing::ValuesIn(kRefusals), test::VerdictCaseName());

// What only the API can send: numbers the YAML parser refuses.
TEST(TrafficRefusalsFromTheApi, NonFiniteNumbers) {
  const double inf = std::numeric_limits<double>::infinity(), nan = std::numeric_limits<double>::quiet_NaN();
  v1::Scenario s;
  ASSERT_FALSE(parse_scenario(with_traffic("  enabled: true\n  plans: [kuiper]\n"), s));
  ASSERT_FALSE(validate_scenario(s));
  auto error_of = [](v1::Scenario copy, auto change) {
    change(*copy.mutable_traffic());
    auto e = validate_scenario(copy);
    return e ? e->message() : std::string();
  };
  EXPECT_EQ(error_of(s, [&](v1::Traffic& t) { t.mutable_disposal()->set_target_lifetime_years(inf); }),
            "traffic.disposal.target_lifetime_years: must be a finite number, got inf");
  EXPECT_EQ(error_of(s, [&](v1::Traffic& t) { t.mutable_disposal()->set_success_probability(nan); }),
            "traffic.disposal.success_probability: must be in [0, 1], got nan");
  EXPECT_EQ(error_of(s, [&](v1::Traffic& t) { t.mutable_business_as_usual()->set_window_years(-inf); }),
            "traffic.business_as_usual.window_years: must be a finite number, got -inf");
}

TEST(TrafficMapping, DisposalReachesTheSettingsAndDefaultsAreTheCores) {
  v1::Scenario s;
  ASSERT_FALSE(parse_scenario(
      with_traffic("  enabled: true\n  plans: [kuiper]\n"
                   "  disposal: {success_probability: 0.75, target_lifetime_years: 5, deorbit: true}\n"),
      s));
  ASSERT_FALSE(validate_scenario(s));
  TrafficSettings t = to_simulation_config(s).traffic;
  EXPECT_TRUE(t.enabled);
  EXPECT_EQ(t.disposal.success_probability, 0.75);
  EXPECT_EQ(t.disposal.target_lifetime_years, 5.0);
  EXPECT_TRUE(t.disposal.deorbit);
  EXPECT_TRUE(t.launches.empty());  // files: traffic_launches_of
  for (const char* text :
       {"population: {synthetic: {objects: 5}}", "population: {synthetic: {objects: 5}}\ntraffic: {}",
        "population: {synthetic: {objects: 5}}\ntraffic: {enabled: false, plans: [kuiper]}"}) {
    ASSERT_FALSE(parse_scenario(text, s));
    ASSERT_FALSE(validate_scenario(s)) << text;
    t = to_simulation_config(s).traffic;
    const DisposalSettings d;
    EXPECT_FALSE(t.enabled) << text;
    EXPECT_EQ(t.disposal.success_probability, d.success_probability);
    EXPECT_EQ(t.disposal.target_lifetime_years, d.target_lifetime_years);
    EXPECT_EQ(t.disposal.deorbit, d.deorbit);
    std::vector<PlannedObject> launches{PlannedObject{}};
    ASSERT_FALSE(traffic_launches_of(s, to_simulation_config(s), {"/nonexistent", "/nonexistent"}, launches));
    EXPECT_TRUE(launches.empty()) << "disabled traffic reads nothing and launches nothing";
  }
}

std::vector<PlannedObject> launches_of(const v1::Scenario& s, const BuildOptions& o = {}) {
  std::vector<PlannedObject> out;
  auto e = traffic_launches_of(s, to_simulation_config(s), {o.traffic_dir, o.datasets_dir}, out);
  EXPECT_FALSE(e) << e->message();
  return out;
}

// Ten objects spread over 01:00..03:00 in two planes; a row at the run's end and one before its start
// launch nothing.
TEST(TrafficMapping, AnInlinePlanGivesItsObjectsAtTheirEpochs) {
  v1::Scenario s;
  ASSERT_FALSE(parse_scenario(
      with_traffic("  enabled: true\n" + inline_plan(kGoodRow + "\nlate,2022-01-02T00:00:00Z,,5,600,97,1"
                                                                "\nearly,2021-12-31T23:00:00Z,,5,600,97,1")),
      s));
  ASSERT_FALSE(validate_scenario(s));
  const std::vector<PlannedObject> launches = launches_of(s);
  ASSERT_EQ(launches.size(), 10u);
  for (std::size_t k = 0; k < launches.size(); ++k) {
    EXPECT_EQ(launches[k].row, 0u);
    EXPECT_EQ(launches[k].index, k);
    EXPECT_NEAR(launches[k].epoch_offset_s, 3600.0 + 7200.0 * static_cast<double>(k) / 9.0, 1e-6);
    EXPECT_NEAR(launches[k].elements.inclination_rad, 53.0 * M_PI / 180.0, 1e-12);
  }
  // Planes 2 of 5: the second plane's RAAN is 180 degrees from the first's.
  EXPECT_NEAR(
      std::abs(std::remainder(launches[5].elements.raan_rad - launches[0].elements.raan_rad, 2 * M_PI)), M_PI,
      1e-9);
}

// Rows in order: the inline plan's, then each named plan's in the listed order.
TEST(TrafficMapping, NamedPlansLoadAfterTheInlineRowsInTheListedOrder) {
  v1::Scenario s;
  ASSERT_FALSE(parse_scenario(
      with_traffic("  enabled: true\n  plans: [oneweb-phase1, starlink-gen1]\n" + inline_plan(kGoodRow)), s));
  s.set_duration_days(30);
  ASSERT_FALSE(validate_scenario(s));
  const BuildOptions options;
  LaunchPlan plan;
  const SimulationConfig c = to_simulation_config(s);
  ASSERT_FALSE(traffic_plan_of(s.traffic(), c.start_epoch, c.start_epoch.plus_seconds(c.duration_s),
                               {options.traffic_dir, options.datasets_dir}, plan));
  ASSERT_EQ(plan.rows.size(), 1u + 1u + 5u);
  EXPECT_EQ(plan.rows[0].label, "a");
  EXPECT_EQ(plan.rows[1].label.rfind("OneWeb", 0), 0u) << plan.rows[1].label;
  EXPECT_EQ(plan.rows[1].count, 588u);
  for (std::size_t r = 2; r < plan.rows.size(); ++r)
    EXPECT_EQ(plan.rows[r].label.rfind("Starlink", 0), 0u) << plan.rows[r].label;
  const std::vector<PlannedObject> launches = launches_of(s);
  std::size_t inline_objects = 0, oneweb = 0, starlink = 0;
  for (const PlannedObject& o : launches) {
    inline_objects += o.row == 0;
    oneweb += o.row == 1;
    starlink += o.row >= 2;
    EXPECT_GE(o.epoch_offset_s, 0.0);
    EXPECT_LT(o.epoch_offset_s, 30 * 86400.0);
  }
  EXPECT_EQ(inline_objects, 10u);
  EXPECT_GT(oneweb, 20u);    // 588 over 2022-01-01..2023-06-01: ~34 in 30 days
  EXPECT_GT(starlink, 50u);  // shell 1: 1584 over two years, ~65 in 30 days
  for (std::size_t k = 1; k < launches.size(); ++k)
    EXPECT_LE(launches[k - 1].epoch_offset_s, launches[k].epoch_offset_s);
}

TEST(TrafficMapping, AMissingPlanFileIsAnErrorOfItsEntry) {
  v1::Scenario s;
  ASSERT_FALSE(parse_scenario(with_traffic("  enabled: true\n  plans: [kuiper, oneweb-phase1]\n"), s));
  BuildOptions options;
  options.traffic_dir = "/nonexistent";
  FieldError error;
  EXPECT_FALSE(build_simulation(s, options, &error));
  EXPECT_EQ(error.path, "traffic.plans[0]");
  EXPECT_EQ(error.reason, "cannot read the shipped plan '/nonexistent/kuiper.csv'");
}

// Business as usual from the bundled SATCAT and catalog: the 2014-2022 window's launches of 2014 (those
// still in the 2022 catalog), relaunched 8 years on in the run's year, after the inline rows.
TEST(TrafficMapping, BusinessAsUsualGivesTheWindowsLaunchesAfterTheOtherRows) {
  v1::Scenario s;
  ASSERT_FALSE(parse_scenario(
      "start_epoch: 2022-01-01T00:00:00Z\nduration_days: 365\npopulation: {synthetic: {objects: 10}}\n"
      "traffic:\n  enabled: true\n  business_as_usual: {enabled: true}\n" +
          inline_plan(kGoodRow),
      s));
  ASSERT_FALSE(validate_scenario(s));
  const BuildOptions options;
  const SimulationConfig c = to_simulation_config(s);
  LaunchPlan plan;
  ASSERT_FALSE(traffic_plan_of(s.traffic(), c.start_epoch, c.start_epoch.plus_seconds(c.duration_s),
                               {options.traffic_dir, options.datasets_dir}, plan));
  ASSERT_GT(plan.rows.size(), 101u);  // hundreds of 2014's launches are still in orbit in 2022
  EXPECT_EQ(plan.rows[0].label, "a");
  for (std::size_t r = 1; r < plan.rows.size(); ++r) {
    EXPECT_EQ(plan.rows[r].label.rfind("business as usual: ", 0), 0u) << plan.rows[r].label;
    const double t = plan.rows[r].epoch.seconds_since(c.start_epoch);
    EXPECT_GE(t, 0.0);
    EXPECT_LT(t, c.duration_s);
  }
  // The window 2020 (one year, ending 2021-01-01): its launches repeat yearly from window_end, in 2021
  // (before the run: not launched) and in 2022.
  s.mutable_traffic()->mutable_business_as_usual()->set_window_end("2021-01-01T00:00:00Z");
  s.mutable_traffic()->mutable_business_as_usual()->set_window_years(1);
  ASSERT_FALSE(validate_scenario(s));
  LaunchPlan one_year;
  ASSERT_FALSE(traffic_plan_of(s.traffic(), c.start_epoch, c.start_epoch.plus_seconds(c.duration_s),
                               {options.traffic_dir, options.datasets_dir}, one_year));
  ASSERT_GT(one_year.rows.size(), 1001u);  // Starlink alone launched over 800 in 2020
  const UtcEpoch window_end = *UtcEpoch::parse_iso8601("2021-01-01T00:00:00Z");
  std::size_t in_run = 0;
  for (std::size_t r = 1; r < one_year.rows.size(); ++r) {
    EXPECT_GE(one_year.rows[r].epoch.seconds_since(window_end), 0.0);
    EXPECT_LT(one_year.rows[r].epoch.seconds_since(c.start_epoch), c.duration_s);
    in_run += one_year.rows[r].epoch.seconds_since(c.start_epoch) >= 0.0;
  }
  EXPECT_GT(in_run, 500u);
  EXPECT_LT(in_run, one_year.rows.size() - 500u);
  std::size_t launched_bau = 0;
  for (const PlannedObject& o : launches_of(s)) launched_bau += o.row >= 1;
  EXPECT_EQ(launched_bau, in_run);
}

class Lifecycle : public EventSink {
 public:
  void on_encounter(std::uint64_t, const Encounter&) override {}
  void on_burn_up(std::uint64_t, const BurnUp&) override {}
  void on_progress(std::uint64_t, const Progress&) override {}
  void on_lifecycle(std::uint64_t, const LifecycleReport& r) override { reports.push_back(r); }
  void on_checkpoint(std::uint64_t, std::int64_t, const std::string& bytes) override { checkpoint = bytes; }
  void on_finished(const RunSummary&) override {}
  void on_failed(const std::string&) override {}
  std::vector<LifecycleReport> reports;
  std::string checkpoint;
};

// A built run launches the plan's objects: ids from kFirstLaunchId, at the step boundaries after their
// epochs.
TEST(TrafficMapping, ABuiltRunLaunchesThePlannedObjects) {
  v1::Scenario s;
  ASSERT_FALSE(parse_scenario(
      "start_epoch: 2022-01-01T00:00:00Z\nduration_days: 0.15\npopulation: {synthetic: {objects: 20}}\n"
      "conjunctions: {enabled: false}\ntraffic:\n  enabled: true\n" +
          inline_plan(kGoodRow),
      s));
  BuildOptions options;
  options.threads = 1;
  options.checkpoints = false;
  FieldError error;
  auto sim = build_simulation(s, options, &error);
  ASSERT_TRUE(sim) << error.message();
  Lifecycle sink;
  RunControl control;
  const RunSummary summary = sim->run(sink, control);
  std::uint64_t launched = 0;
  ObjectId next = kFirstLaunchId;
  for (const LifecycleReport& r : sink.reports) {
    ASSERT_EQ(r.kind, LifecycleEventKind::kLaunch);
    EXPECT_EQ(r.first_id, next);
    EXPECT_EQ(r.row, 0u);
    EXPECT_GE(r.time_s, 3600.0);
    EXPECT_LE(r.time_s, 3 * 3600.0 + 30.0);
    launched += r.last_id - r.first_id + 1;
    next = r.last_id + 1;
  }
  EXPECT_EQ(launched, 10u);
  EXPECT_EQ(summary.objects_final, 30u);
}

// Traffic off leaves the run's key alone: a checkpoint of a run without the block resumes under a
// scenario with a disabled block (whatever its other fields), so existing runs keep their fingerprints.
TEST(TrafficMapping, DisabledTrafficKeepsTheRunsKey) {
  const std::string base =
      "population: {synthetic: {objects: 20}}\nduration_days: 0.01\ndt_s: 30\ncheckpoints: {every_steps: "
      "5}\n";
  v1::Scenario without, disabled, enabled;
  ASSERT_FALSE(parse_scenario(base, without));
  ASSERT_FALSE(parse_scenario(base + "traffic: {enabled: false, plans: [kuiper], disposal: {deorbit: true}}",
                              disabled));
  ASSERT_FALSE(parse_scenario(base + "traffic: {enabled: true, plans: [kuiper]}", enabled));
  BuildOptions options;
  options.threads = 1;
  FieldError error;
  auto sim = build_simulation(without, options, &error);
  ASSERT_TRUE(sim) << error.message();
  Lifecycle sink;
  RunControl control;
  sim->run(sink, control);
  ASSERT_FALSE(sink.checkpoint.empty());
  EXPECT_TRUE(resume_simulation(disabled, sink.checkpoint, options, &error)) << error.message();
  EXPECT_FALSE(resume_simulation(enabled, sink.checkpoint, options, &error));
  EXPECT_EQ(error.path, "checkpoint");
}

// The shipped scenario: 322 objects of its inline plan on the first day, then the named plans' share.
TEST(ConstellationsScenario, LaunchesItsInlinePlanOnTheFirstDay) {
  v1::Scenario s;
  auto e = load_scenario_file(kConstellations, s);
  ASSERT_FALSE(e) << e->message();
  ASSERT_FALSE(validate_scenario(s));
  const std::vector<PlannedObject> launches = launches_of(s);
  std::size_t first_day = 0, named = 0;
  for (const PlannedObject& o : launches) {
    if (o.row < 4) {
      ++first_day;
      EXPECT_LT(o.epoch_offset_s, 86400.0);
    } else {
      ++named;
    }
  }
  EXPECT_EQ(first_day, 240u + 60u + 2u + 20u);
  EXPECT_GT(named, 0u);
}

}  // namespace
}  // namespace kessler
