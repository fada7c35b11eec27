// Scenarios built into real runs (the project's propagator and loaders): thread-count independence and
// resume bit for bit, refusals before anything runs.
#include <gtest/gtest.h>

#include <filesystem>
#include <map>
#include <optional>

#include "core/scenario/run_builder.hpp"

namespace kessler {
namespace {

class Recorder : public EventSink {
 public:
  std::vector<std::pair<std::uint64_t, std::string>> checkpoints;
  std::uint64_t last_seq = 0, events = 0;
  std::int64_t stop_at_step = -1;
  RunControl* control = nullptr;
  void on_encounter(std::uint64_t seq, const Encounter&) override { saw(seq); }
  void on_burn_up(std::uint64_t seq, const BurnUp&) override { saw(seq); }
  void on_progress(std::uint64_t seq, const Progress& p) override {
    saw(seq);
    if (p.step == stop_at_step) control->cancel = true;
  }
  void on_checkpoint(std::uint64_t seq, std::int64_t, const std::string& bytes) override {
    checkpoints.emplace_back(seq, bytes);
  }
  void on_finished(const RunSummary&) override {}
  void on_failed(const std::string&) override {}

 private:
  void saw(std::uint64_t seq) {
    EXPECT_EQ(seq, last_seq + 1) << "sequence numbers must have no gaps";
    last_seq = seq;
    ++events;
  }
};

v1::Scenario leo_subset(const char* extra = "") {
  v1::Scenario s;
  std::string text = std::string(R"(
population: {dataset: leo-19647, max_objects: 4000}
duration_days: 0.02
dt_s: 10
force_model: {srp: false, atmosphere: exponential_fit}
conjunctions: {screening_distance_km: 10}
progress_every_steps: 1
checkpoints: {every_steps: 25}
)") + extra;
  auto e = parse_scenario(text, s);
  EXPECT_FALSE(e) << e->message();
  return s;
}

RunSummary run(const v1::Scenario& s, int threads, Recorder& sink, RunControl& control) {
  BuildOptions options;
  options.threads = threads;
  FieldError error;
  auto sim = build_simulation(s, options, &error);
  EXPECT_TRUE(sim) << error.message();
  sink.control = &control;
  return sim->run(sink, control);
}

TEST(RunBuilder, Leo19647RunsAreThreadCountIndependent) {
  auto s = leo_subset();
  Recorder a;
  RunControl ca;
  auto one = run(s, 1, a, ca);
  EXPECT_EQ(one.steps, 172);
  EXPECT_EQ(one.objects_initial, 4000u);
  EXPECT_GT(one.conjunctions, 3u) << "the comparison needs encounters to compare";
  for (int threads : {2, 4}) {
    Recorder b;
    RunControl cb;
    auto many = run(s, threads, b, cb);
    EXPECT_EQ(one.state_digest, many.state_digest) << threads << " threads";
    EXPECT_EQ(one.events_digest, many.events_digest) << threads << " threads";
    EXPECT_EQ(one.events, many.events);
  }
}

TEST(RunBuilder, DragAtTheStepsEndsIsThreadCountIndependentAndResumesBitForBit) {
  v1::Scenario s = leo_subset();
  s.mutable_force_model()->set_drag_coupling(v1::DRAG_COUPLING_STEP_ENDS);
  Recorder a, b, every_sink, first;
  RunControl ca, cb, ce, c1;
  const auto one = run(s, 1, a, ca);
  const auto two = run(s, 2, b, cb);
  EXPECT_EQ(one.state_digest, two.state_digest);
  EXPECT_EQ(one.events_digest, two.events_digest);
  // The setting reaches the propagator: the states differ from drag coupled at every kick.
  const auto every = run(leo_subset(), 1, every_sink, ce);
  EXPECT_NE(one.state_digest, every.state_digest);
  first.stop_at_step = 90;
  ASSERT_TRUE(run(s, 2, first, c1).cancelled);
  ASSERT_FALSE(first.checkpoints.empty());
  BuildOptions options;
  options.threads = 1;
  FieldError error;
  auto resumed = resume_simulation(s, first.checkpoints.back().second, options, &error);
  ASSERT_TRUE(resumed) << error.message();
  Recorder rest;
  rest.last_seq = first.checkpoints.back().first;
  RunControl c3;
  const auto finished = resumed->run(rest, c3);
  EXPECT_EQ(finished.state_digest, one.state_digest);
  EXPECT_EQ(finished.events_digest, one.events_digest);
}

TEST(RunBuilder, Leo19647ResumesBitForBit) {
  auto s = leo_subset();
  Recorder whole_sink, first;
  RunControl c1, c2;
  auto whole = run(s, 2, whole_sink, c1);
  first.stop_at_step = 90;
  auto stopped = run(s, 2, first, c2);
  ASSERT_TRUE(stopped.cancelled);
  ASSERT_FALSE(first.checkpoints.empty());
  BuildOptions options;
  options.threads = 1;
  FieldError error;
  auto resumed = resume_simulation(s, first.checkpoints.back().second, options, &error);
  ASSERT_TRUE(resumed) << error.message();
  EXPECT_EQ(resumed->step(), 75);
  Recorder rest;
  rest.last_seq = first.checkpoints.back().first;
  RunControl c3;
  auto finished = resumed->run(rest, c3);
  EXPECT_EQ(finished.state_digest, whole.state_digest);
  EXPECT_EQ(finished.events_digest, whole.events_digest);
  EXPECT_EQ(rest.last_seq, whole_sink.last_seq);
  EXPECT_GT(finished.conjunctions, 0u);
}

TEST(RunBuilder, ACheckpointOfAnotherScenarioIsRefused) {
  auto s = leo_subset();
  Recorder sink;
  sink.stop_at_step = 30;
  RunControl c;
  run(s, 1, sink, c);
  ASSERT_FALSE(sink.checkpoints.empty());
  auto other = leo_subset();
  other.set_dt_s(5);
  FieldError error;
  EXPECT_FALSE(resume_simulation(other, sink.checkpoints.back().second, BuildOptions{}, &error));
  EXPECT_EQ(error.path, "checkpoint");
  EXPECT_NE(error.reason.find("different scenario"), std::string::npos) << error.reason;
  std::string corrupt = sink.checkpoints.back().second;
  corrupt[100] ^= 1;
  EXPECT_FALSE(resume_simulation(s, corrupt, BuildOptions{}, &error));
  EXPECT_EQ(error.message(), "checkpoint: checkpoint: checksum mismatch (corrupt bytes)");
}

TEST(RunBuilder, SyntheticRunsAreThreadCountIndependent) {
  v1::Scenario s;
  ASSERT_FALSE(parse_scenario(R"(
population: {synthetic: {objects: 800, min_altitude_km: 500, max_altitude_km: 520}}
duration_days: 0.01
conjunctions: {screening_distance_km: 20}
seed: 11
)",
                              s));
  Recorder a, b;
  RunControl ca, cb;
  auto one = run(s, 1, a, ca);
  auto two = run(s, 2, b, cb);
  EXPECT_EQ(one.objects_initial, 800u);
  EXPECT_GT(one.events, 0u);
  EXPECT_EQ(one.events_digest, two.events_digest);
  EXPECT_EQ(one.state_digest, two.state_digest);
}

// Two objects given as states, set to meet at 7000 km on crossing tracks 5 s after the start: the run
// reports their close approach at about 5 s (gravity bends both tracks almost alike).
TEST(RunBuilder, StateTableObjectsMeetWhereTheyWereAimed) {
  v1::Scenario s;
  ASSERT_FALSE(parse_scenario(R"(
population:
  state_table: |
    1,2022-01-01T00:00:00Z,7000000.0,-37730.0,0,0,7546.0,0,2.0,,
    2,2022-01-01T00:00:00Z,7000000.0,-18865.0,-32675.13848478687,0,3773.0,6535.027696957373,2.0,,
duration_days: 0.001
force_model: {j2: false, c22_s22: false, drag: false, srp: false}
conjunctions: {screening_distance_km: 1}
)",
                              s));
  struct Encounters : Recorder {
    std::vector<Encounter> seen;
    void on_encounter(std::uint64_t seq, const Encounter& e) override {
      Recorder::on_encounter(seq, e);
      seen.push_back(e);
    }
  } sink;
  RunControl control;
  BuildOptions options;
  FieldError error;
  auto sim = build_simulation(s, options, &error);
  ASSERT_TRUE(sim) << error.message();
  sink.control = &control;
  sim->run(sink, control);
  ASSERT_EQ(sink.seen.size(), 1u);
  EXPECT_EQ(sink.seen[0].id1, 1u);
  EXPECT_EQ(sink.seen[0].id2, 2u);
  EXPECT_NEAR(sink.seen[0].tca_s, 5.0, 0.05);
  EXPECT_LT(sink.seen[0].miss_distance_m, 100.0);
}

// A debris fragment whose element set (2022-01-14) is older than its decay: SGP4 puts it at ~20 km at the
// start. It leaves at ingest under the scenario's burn-up altitude instead of burning up at the first step.
TEST(RunBuilder, ObjectsDecayedBeforeTheStartLeaveAtIngest) {
  const std::string catalog = R"(
start_epoch: 2022-01-22T00:00:00Z
population:
  catalog:
    format: tle
    text: |
      0 COSMOS 1408 DEB
      1 50282U 82092YX  22014.57637332  .04559140  00000-0  36701+0 0  9997
      2 50282  81.8160  62.2954 0168097 258.3864  99.8441 14.85036373  7662
      0 NOAA 20
      1 43013U 17073A   22022.53093932  .00000030  00000-0  34940-4 0  9998
      2 43013  98.7439 323.0548 0001454  96.5825 263.5517 14.19525157216522
)";
  for (const auto& [extra, objects] : {std::pair{"", 1u}, std::pair{"burn_up_altitude_km: 10\n", 2u}}) {
    v1::Scenario s;
    ASSERT_FALSE(parse_scenario(catalog + extra, s));
    FieldError error;
    auto sim = build_simulation(s, BuildOptions{}, &error);
    ASSERT_TRUE(sim) << error.message();
    EXPECT_EQ(sim->population().size(), objects) << extra;
    EXPECT_TRUE(sim->population().index_of(43013)) << extra;
  }
}

TEST(RunBuilder, BadScenariosAreRefusedBeforeAnythingRuns) {
  struct Bad {
    const char* text;
    const char* message;
  };
  for (const Bad& bad : {
           Bad{"population: {dataset: leo-19647}\ndt_s: 0", "dt_s: must be positive, got 0"},
           Bad{"population: {dataset: leo-19647}\ndt_s: -1", "dt_s: must be positive, got -1"},
           Bad{"population: {dataset: leo-19647}\nduration_days: 0.00001",
               "duration_days: the run (0.864 s) is shorter than one step (dt_s = 30 s)"},
       }) {
    v1::Scenario s;
    ASSERT_FALSE(parse_scenario(bad.text, s));
    FieldError error;
    EXPECT_FALSE(build_simulation(s, BuildOptions{}, &error));
    EXPECT_EQ(error.message(), bad.message);
  }
  {
    // Only the ISS, which the paper's exclusions leave out.
    v1::Scenario iss;
    ASSERT_FALSE(parse_scenario(R"(
start_epoch: 2022-01-23T00:00:00Z
population:
  catalog:
    format: tle
    text: |
      0 ISS (ZARYA)
      1 25544U 98067A   22022.91470718  .00005958  00000-0  11386-3 0  9994
      2 25544  51.6445 336.0056 0006830  51.7508  17.5213 15.49594026322655
)",
                                iss));
    FieldError error;
    EXPECT_FALSE(build_simulation(iss, BuildOptions{}, &error));
    EXPECT_EQ(error.path, "population");
    EXPECT_EQ(error.reason.rfind("no objects are left after the ingest filters", 0), 0u) << error.reason;
  }
  v1::Scenario s;
  ASSERT_FALSE(parse_scenario("population: {dataset: leo-19647}\nconjunctions: {enabled: false}", s));
  BuildOptions options;
  options.datasets_dir = "/nonexistent";
  FieldError error;
  EXPECT_FALSE(build_simulation(s, options, &error));
  EXPECT_EQ(error.path, "population");
}

// NRLMSISE-00's solar activity is read from the run's own datasets directory (kesslerd --datasets,
// kessler run --datasets): a directory without a space weather table refuses the scenario, naming the
// field; the constant mode needs no table.
TEST(RunBuilder, SolarActivityComesFromTheRunsDatasets) {
  const std::string dir = testing::TempDir() + "/kessler_datasets_without_space_weather";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  std::filesystem::copy(std::string(KESSLER_DATASETS_DIR) + "/leo-19647", dir + "/leo-19647",
                        std::filesystem::copy_options::recursive);
  BuildOptions options;
  options.datasets_dir = dir;
  v1::Scenario observed;
  ASSERT_FALSE(parse_scenario(R"(
population: {dataset: leo-19647, max_objects: 10}
duration_days: 0.01
conjunctions: {enabled: false}
force_model: {atmosphere: nrlmsise00, solar_activity: {mode: observed}}
)",
                              observed));
  FieldError error;
  EXPECT_FALSE(build_simulation(observed, options, &error));
  EXPECT_EQ(error.path, "force_model.solar_activity");
  EXPECT_NE(error.reason.find("SW-All.csv"), std::string::npos) << error.reason;

  v1::Scenario constant = observed;
  constant.mutable_force_model()->mutable_solar_activity()->set_mode(v1::SOLAR_ACTIVITY_MODE_CONSTANT);
  EXPECT_TRUE(build_simulation(constant, options, &error)) << error.message();

  std::filesystem::create_directories(dir + "/space_weather");
  std::filesystem::copy_file(std::string(KESSLER_DATASETS_DIR) + "/space_weather/SW-All.csv",
                             dir + "/space_weather/SW-All.csv");
  EXPECT_TRUE(build_simulation(observed, options, &error)) << error.message();
  std::filesystem::remove_all(dir);
}

// Every record of a catalog is kept or dropped for one reason: records == kept + the drops.
TEST(RunBuilder, TheIngestReportAccountsForEveryRecord) {
  v1::Scenario scenario;
  auto e = load_scenario_file(KESSLER_SCENARIO_TEST_DATA_DIR "/catalog-small.yaml", scenario);
  ASSERT_FALSE(e) << e->message();
  std::optional<IngestReport> report;
  FieldError error;
  auto sim = build_simulation(scenario, BuildOptions(), &error, &report);
  ASSERT_TRUE(sim) << error.message();
  ASSERT_TRUE(report);
  const IngestOutcome outcome = ingest_outcome(*report);
  std::uint64_t dropped = 0;
  std::map<std::string, std::uint64_t> by_reason;
  for (const auto& [reason, count] : outcome.dropped) {
    dropped += count;
    by_reason[reason] += count;
  }
  EXPECT_EQ(outcome.records, 204u);
  EXPECT_EQ(outcome.records, outcome.kept + dropped);
  EXPECT_EQ(outcome.kept, sim->population().size());
  EXPECT_EQ(by_reason["excluded name"], 2u);
  EXPECT_EQ(by_reason["rejected: checksum"], 1u);

  // A population that is not ingested has no report.
  report.reset();
  ASSERT_TRUE(build_simulation(leo_subset(), BuildOptions(), &error, &report)) << error.message();
  EXPECT_FALSE(report);
}

}  // namespace
}  // namespace kessler
