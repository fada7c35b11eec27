// The scenario's `breakups` block: every refusal with its exact field path and reason, the mapping onto
// BreakupSettings, and the shipped Iridium 33 / Cosmos 2251 replay built from its file.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "core/scenario/run_builder.hpp"
#include "tests/scenario/verdict_table.hpp"

namespace kessler {
namespace {

constexpr const char* kIridiumCosmos = KESSLER_SCENARIOS_DIR "/iridium-cosmos-2009.yaml";

// A synthetic population over the day of the Iridium/Cosmos collision, with `breakups` as given.
std::string with_breakups(const std::string& breakups, const std::string& extra = "") {
  return "start_epoch: 2009-02-10T12:00:00Z\nduration_days: 1\npopulation: {synthetic: {objects: 10}}\n" +
         extra + "breakups:\n" + breakups;
}

// Two good events ahead of the one under test, so that paths show the index.
std::string third_event(const std::string& event) {
  return with_breakups(
      "  enabled: true\n  scheduled:\n"
      "    - {epoch: 2009-02-10T13:00:00Z, kind: explosion, objects: [1]}\n"
      "    - {epoch: 2009-02-10T14:00:00Z, kind: collision, objects: [2, 3]}\n"
      "    - " +
      event + "\n");
}

using Case = test::VerdictCase;

const Case kRefusals[] = {
    {"lc zero", with_breakups("  min_characteristic_length_m: 0\n"),
     "breakups.min_characteristic_length_m: must be in (0, 1] m, got 0"},
    {"lc negative", with_breakups("  min_characteristic_length_m: -0.1\n"),
     "breakups.min_characteristic_length_m: must be in (0, 1] m, got -0.1"},
    {"lc above 1 m", with_breakups("  min_characteristic_length_m: 1.5\n"),
     "breakups.min_characteristic_length_m: must be in (0, 1] m, got 1.5"},
    {"separation negative", with_breakups("  separation_s: -1\n"),
     "breakups.separation_s: must not be negative, got -1"},
    {"explosion scale zero", with_breakups("  explosion_scale_s: 0\n"),
     "breakups.explosion_scale_s: must be positive, got 0"},
    {"max fragments zero", with_breakups("  max_fragments_per_event: 0\n"),
     "breakups.max_fragments_per_event: must be at least 1"},
    {"sgp4", with_breakups("  enabled: true\n", "propagator: sgp4\n"),
     "breakups.enabled: breakups need the numerical propagator (SGP4 cannot move fragments, which have no "
     "element sets); set propagator: numerical or leave it out"},
    {"on_collision name", with_breakups("  on_collision: explode\n"),
     "breakups.on_collision: unknown value 'explode' (expected one of: fragment, record_only)"},
    {"kind name", third_event("{epoch: 2009-02-10T15:00:00Z, kind: implosion, objects: [4]}"),
     "breakups.scheduled[2].kind: unknown value 'implosion' (expected one of: explosion, collision)"},
    {"epoch missing", third_event("{kind: explosion, objects: [4]}"),
     "breakups.scheduled[2].epoch: is required (ISO 8601 UTC, e.g. 2009-02-10T16:56:00Z)"},
    {"epoch unparseable", third_event("{epoch: tomorrow, kind: explosion, objects: [4]}"),
     "breakups.scheduled[2].epoch: "},  // the reason is UtcEpoch's; the path is what matters here
    {"epoch before start", third_event("{epoch: 2009-02-10T11:59:59Z, kind: explosion, objects: [4]}"),
     "breakups.scheduled[2].epoch: must be within the run, [2009-02-10T12:00:00Z, 2009-02-11T12:00:00Z), "
     "got 2009-02-10T11:59:59Z"},
    {"epoch at end", third_event("{epoch: 2009-02-11T12:00:00Z, kind: explosion, objects: [4]}"),
     "breakups.scheduled[2].epoch: must be within the run, [2009-02-10T12:00:00Z, 2009-02-11T12:00:00Z), "
     "got 2009-02-11T12:00:00Z"},
    {"kind missing", third_event("{epoch: 2009-02-10T15:00:00Z, objects: [4]}"),
     "breakups.scheduled[2].kind: is required (explosion or collision)"},
    {"explosion of two", third_event("{epoch: 2009-02-10T15:00:00Z, kind: explosion, objects: [4, 5]}"),
     "breakups.scheduled[2].objects: an explosion takes exactly 1 object, got 2"},
    {"explosion of none", third_event("{epoch: 2009-02-10T15:00:00Z, kind: explosion}"),
     "breakups.scheduled[2].objects: an explosion takes exactly 1 object, got 0"},
    {"collision of one", third_event("{epoch: 2009-02-10T15:00:00Z, kind: collision, objects: [4]}"),
     "breakups.scheduled[2].objects: a collision takes exactly 2 objects, got 1"},
    {"collision of three", third_event("{epoch: 2009-02-10T15:00:00Z, kind: collision, objects: [4, 5, 6]}"),
     "breakups.scheduled[2].objects: a collision takes exactly 2 objects, got 3"},
    {"collision with itself", third_event("{epoch: 2009-02-10T15:00:00Z, kind: collision, objects: [4, 4]}"),
     "breakups.scheduled[2].objects[1]: is objects[0] again (4); a collision takes two distinct objects"},
    {"impact speed negative",
     third_event("{epoch: 2009-02-10T15:00:00Z, kind: collision, objects: [4, 5], impact_speed_m_s: -3}"),
     "breakups.scheduled[2].impact_speed_m_s: must not be negative, got -3"},
    {"impact speed of an explosion",
     third_event("{epoch: 2009-02-10T15:00:00Z, kind: explosion, objects: [4], impact_speed_m_s: 100}"),
     "breakups.scheduled[2].impact_speed_m_s: only a collision takes an impact speed"},
    {"one mass of two",
     third_event("{epoch: 2009-02-10T15:00:00Z, kind: collision, objects: [4, 5], masses_kg: [10]}"),
     "breakups.scheduled[2].masses_kg: give one mass per object (2) or none, got 1"},
    {"mass zero",
     third_event("{epoch: 2009-02-10T15:00:00Z, kind: collision, objects: [4, 5], masses_kg: [10, 0]}"),
     "breakups.scheduled[2].masses_kg[1]: must be positive, got 0"},
    {"mass negative",
     third_event("{epoch: 2009-02-10T15:00:00Z, kind: explosion, objects: [4], masses_kg: [-2]}"),
     "breakups.scheduled[2].masses_kg[0]: must be positive, got -2"},
    // N = 6 S Lc^-1.6 = 238.9 at S = 1, Lc = 0.1 m.
    {"explosion over the fragment limit",
     with_breakups("  max_fragments_per_event: 200\n  scheduled:\n"
                   "    - {epoch: 2009-02-10T13:00:00Z, kind: explosion, objects: [1]}\n"),
     "breakups.scheduled[0]: gives 238 fragments of at least 0.1 m, more than max_fragments_per_event (200)"},
    // Iridium/Cosmos at 11.7 km/s: catastrophic, M = 1510 kg, N = 0.1 M^0.75 Lc^-1.71 = 1242.
    {"collision over the fragment limit",
     with_breakups("  max_fragments_per_event: 1000\n  scheduled:\n"
                   "    - {epoch: 2009-02-10T16:56:00Z, kind: collision, objects: [1, 2], "
                   "impact_speed_m_s: 11700, masses_kg: [560, 950]}\n"),
     "breakups.scheduled[0]: gives 1242 fragments of at least 0.1 m, more than max_fragments_per_event "
     "(1000)"},
};

class BreakupRefusals : public ::testing::TestWithParam<Case> {};

TEST_P(BreakupRefusals, NameTheFieldAndTheReason) {
  test::expect_verdict(GetParam());
}

INSTANTIATE_TEST_SUITE_P(Table, BreakupRefusals, ::testing::ValuesIn(kRefusals), test::VerdictCaseName());

// What only the API can send: numbers the YAML parser refuses (non-finite values, unknown enum numbers).
v1::Scenario api_scenario() {
  v1::Scenario s;
  EXPECT_FALSE(
      parse_scenario(third_event("{epoch: 2009-02-10T15:00:00Z, kind: collision, objects: [4, 5]}"), s));
  EXPECT_FALSE(validate_scenario(s));
  return s;
}

std::string api_error(const v1::Scenario& s) {
  auto e = validate_scenario(s);
  return e ? e->message() : "";
}

TEST(BreakupRefusalsFromTheApi, NonFiniteNumbers) {
  const double inf = std::numeric_limits<double>::infinity(), nan = std::numeric_limits<double>::quiet_NaN();
  v1::Scenario s = api_scenario();
  s.mutable_breakups()->set_min_characteristic_length_m(nan);
  EXPECT_EQ(api_error(s), "breakups.min_characteristic_length_m: must be in (0, 1] m, got nan");
  s = api_scenario();
  s.mutable_breakups()->set_separation_s(inf);
  EXPECT_EQ(api_error(s), "breakups.separation_s: must be a finite number, got inf");
  s = api_scenario();
  s.mutable_breakups()->set_explosion_scale_s(nan);
  EXPECT_EQ(api_error(s), "breakups.explosion_scale_s: must be a finite number, got nan");
  s = api_scenario();
  s.mutable_breakups()->mutable_scheduled(2)->set_impact_speed_m_s(inf);
  EXPECT_EQ(api_error(s), "breakups.scheduled[2].impact_speed_m_s: must be a finite number, got inf");
  s = api_scenario();
  s.mutable_breakups()->mutable_scheduled(2)->add_masses_kg(100);
  s.mutable_breakups()->mutable_scheduled(2)->add_masses_kg(-inf);
  EXPECT_EQ(api_error(s), "breakups.scheduled[2].masses_kg[1]: must be a finite number, got -inf");
}

TEST(BreakupRefusalsFromTheApi, UnknownEnumNumbers) {
  v1::Scenario s = api_scenario();
  s.mutable_breakups()->set_on_collision(static_cast<v1::CollisionResponse>(7));
  EXPECT_EQ(api_error(s), "breakups.on_collision: unknown value 7 (expected one of: fragment, record_only)");
  s = api_scenario();
  s.mutable_breakups()->mutable_scheduled(2)->set_kind(static_cast<v1::BreakupKind>(9));
  EXPECT_EQ(api_error(s),
            "breakups.scheduled[2].kind: unknown value 9 (expected one of: explosion, collision)");
}

TEST(BreakupMapping, EveryFieldReachesTheSettings) {
  v1::Scenario s;
  ASSERT_FALSE(parse_scenario(with_breakups(R"(  enabled: true
  on_collision: record_only
  separation_s: 120
  min_characteristic_length_m: 0.05
  mass_conservation: false
  explosion_scale_s: 0.5
  max_fragments_per_event: 50000
  scheduled:
    - {epoch: 2009-02-10T12:30:00Z, kind: explosion, objects: [7], masses_kg: [1200]}
    - {epoch: "2009-02-10T16:56:00Z", kind: BREAKUP_KIND_COLLISION, objects: [1, 2], impact_speed_m_s: 11700}
)"),
                              s));
  ASSERT_FALSE(validate_scenario(s));
  const BreakupSettings b = to_simulation_config(s).breakups;
  EXPECT_TRUE(b.enabled);
  EXPECT_EQ(b.on_collision, CollisionResponse::kRecordOnly);
  EXPECT_EQ(b.separation_s, 120.0);
  EXPECT_EQ(b.min_characteristic_length_m, 0.05);
  EXPECT_FALSE(b.mass_conservation);
  EXPECT_EQ(b.explosion_scale, 0.5);
  EXPECT_EQ(b.max_fragments_per_event, 50000u);
  ASSERT_EQ(b.scheduled.size(), 2u);
  EXPECT_FALSE(b.scheduled[0].step);
  EXPECT_NEAR(b.scheduled[0].epoch_offset_s, 1800.0, 1e-6);
  EXPECT_EQ(b.scheduled[0].kind, BreakupKind::kExplosion);
  EXPECT_EQ(b.scheduled[0].object_ids, std::vector<ObjectId>{7});
  EXPECT_FALSE(b.scheduled[0].impact_speed_m_s);
  EXPECT_EQ(b.scheduled[0].masses_kg, std::vector<double>{1200.0});
  EXPECT_NEAR(b.scheduled[1].epoch_offset_s, 17760.0, 1e-6);
  EXPECT_EQ(b.scheduled[1].kind, BreakupKind::kCollision);
  EXPECT_EQ(b.scheduled[1].object_ids, (std::vector<ObjectId>{1, 2}));
  EXPECT_EQ(b.scheduled[1].impact_speed_m_s, 11700.0);
  EXPECT_TRUE(b.scheduled[1].masses_kg.empty());
}

void expect_default_settings(const BreakupSettings& b) {
  const BreakupSettings d;
  EXPECT_FALSE(b.enabled);
  EXPECT_EQ(b.on_collision, d.on_collision);
  EXPECT_EQ(b.separation_s, d.separation_s);
  EXPECT_EQ(b.min_characteristic_length_m, d.min_characteristic_length_m);
  EXPECT_EQ(b.mass_conservation, d.mass_conservation);
  EXPECT_EQ(b.explosion_scale, d.explosion_scale);
  EXPECT_EQ(b.max_fragments_per_event, d.max_fragments_per_event);
  EXPECT_TRUE(b.scheduled.empty());
}

TEST(BreakupMapping, NoBreakupsBlockGivesTheCoreDefaults) {
  v1::Scenario s;
  ASSERT_FALSE(parse_scenario("population: {synthetic: {objects: 5}}", s));
  expect_default_settings(to_simulation_config(s).breakups);
  ASSERT_FALSE(parse_scenario("population: {synthetic: {objects: 5}}\nbreakups: {}", s));
  expect_default_settings(to_simulation_config(s).breakups);
  ASSERT_FALSE(
      parse_scenario("population: {synthetic: {objects: 5}}\nbreakups: {on_collision: fragment}", s));
  EXPECT_EQ(to_simulation_config(s).breakups.on_collision, CollisionResponse::kFragment);
}

class NoEvents : public NullSink {
 public:
  void on_checkpoint(std::uint64_t, std::int64_t, const std::string& bytes) override { checkpoint = bytes; }
  std::string checkpoint;
};

// Disabled breakups leave the run's key alone: a checkpoint of a run without the block resumes under a
// scenario with a disabled block (whatever its other fields), so existing runs keep their fingerprints.
TEST(BreakupMapping, DisabledBreakupsKeepTheRunsKey) {
  const std::string base =
      "population: {synthetic: {objects: 20}}\nduration_days: 0.01\ndt_s: 30\ncheckpoints: {every_steps: "
      "5}\n";
  v1::Scenario without, disabled, enabled;
  ASSERT_FALSE(parse_scenario(base, without));
  ASSERT_FALSE(
      parse_scenario(base + "breakups: {enabled: false, separation_s: 60, explosion_scale_s: 2}", disabled));
  ASSERT_FALSE(parse_scenario(base + "breakups: {enabled: true}", enabled));
  BuildOptions options;
  options.threads = 1;
  FieldError error;
  auto sim = build_simulation(without, options, &error);
  ASSERT_TRUE(sim) << error.message();
  NoEvents sink;
  RunControl control;
  sim->run(sink, control);
  ASSERT_FALSE(sink.checkpoint.empty());
  EXPECT_TRUE(resume_simulation(disabled, sink.checkpoint, options, &error)) << error.message();
  EXPECT_FALSE(resume_simulation(enabled, sink.checkpoint, options, &error));
  EXPECT_EQ(error.path, "checkpoint");
}

v1::Scenario iridium_cosmos() {
  v1::Scenario s;
  auto e = load_scenario_file(kIridiumCosmos, s);
  EXPECT_FALSE(e) << e->message();
  return s;
}

TEST(IridiumCosmosScenario, BuildsWithBothObjectsAndTheCollisionScheduled) {
  const v1::Scenario s = iridium_cosmos();
  ASSERT_FALSE(validate_scenario(s));
  const SimulationConfig c = to_simulation_config(s);
  EXPECT_TRUE(c.breakups.enabled);
  ASSERT_EQ(c.breakups.scheduled.size(), 1u);
  const ScheduledBreakup& b = c.breakups.scheduled[0];
  EXPECT_NEAR(b.epoch_offset_s, 17760.0, 1e-6);  // 12:00 to 16:56
  EXPECT_EQ(b.kind, BreakupKind::kCollision);
  EXPECT_EQ(b.object_ids, (std::vector<ObjectId>{24946, 22675}));
  EXPECT_EQ(b.masses_kg, (std::vector<double>{560.0, 950.0}));
  EXPECT_FALSE(b.impact_speed_m_s);
  BuildOptions options;
  options.threads = 1;
  options.checkpoints = false;
  FieldError error;
  std::optional<IngestReport> ingest;
  auto sim = build_simulation(s, options, &error, &ingest);
  ASSERT_TRUE(sim) << error.message();
  ASSERT_TRUE(ingest);
  EXPECT_EQ(ingest->records, 2u);
  EXPECT_EQ(ingest->kept, 2u);
}

TEST(IridiumCosmosScenario, AnObjectNotInThePopulationIsRefusedAtBuild) {
  v1::Scenario s = iridium_cosmos();
  s.mutable_breakups()->mutable_scheduled(0)->set_objects(0, 99999);
  ASSERT_FALSE(validate_scenario(s));  // only the population knows
  FieldError error;
  EXPECT_FALSE(build_simulation(s, BuildOptions{}, &error));
  EXPECT_EQ(error.message(), "breakups.scheduled[0].objects[0]: no object 99999 in the population");
}

// A collision at a given speed whose masses are the population's: counted once the population is known.
TEST(IridiumCosmosScenario, TheFragmentLimitIsCheckedWithThePopulationsMasses) {
  v1::Scenario s = iridium_cosmos();
  s.mutable_breakups()->set_max_fragments_per_event(10);
  s.mutable_breakups()->mutable_scheduled(0)->clear_masses_kg();
  s.mutable_breakups()->mutable_scheduled(0)->set_impact_speed_m_s(11700);
  ASSERT_FALSE(validate_scenario(s));
  FieldError error;
  EXPECT_FALSE(build_simulation(s, BuildOptions{}, &error));
  EXPECT_EQ(error.path, "breakups.scheduled[0]");
  EXPECT_NE(error.reason.find("more than max_fragments_per_event (10)"), std::string::npos) << error.reason;
  // Without a speed the count is known only at the breakup: the build goes ahead.
  s.mutable_breakups()->mutable_scheduled(0)->clear_impact_speed_m_s();
  EXPECT_TRUE(build_simulation(s, BuildOptions{}, &error)) << error.message();
}

class Breakups : public NoEvents {
 public:
  std::vector<BreakupReport> reports;
  void on_breakup(std::uint64_t, const BreakupReport& r) override { reports.push_back(r); }
};

// The replay through the collision (6 hours): one catastrophic breakup of both, ~1,242 fragments.
TEST(IridiumCosmosScenario, TheCollisionBreaksBothUp) {
  v1::Scenario s = iridium_cosmos();
  s.set_duration_days(0.25);
  s.mutable_conjunctions()->set_enabled(false);  // the breakup alone is under test
  BuildOptions options;
  options.threads = 2;
  options.checkpoints = false;
  FieldError error;
  auto sim = build_simulation(s, options, &error);
  ASSERT_TRUE(sim) << error.message();
  Breakups sink;
  RunControl control;
  const RunSummary summary = sim->run(sink, control);
  ASSERT_EQ(sink.reports.size(), 1u);
  const BreakupReport& r = sink.reports[0];
  EXPECT_EQ(r.kind, BreakupKind::kCollision);
  EXPECT_NEAR(r.time_s, 17760.0, 1e-6);
  EXPECT_TRUE(r.catastrophic);
  EXPECT_NEAR(static_cast<double>(r.fragment_count), 1242.0, 5.0);
  EXPECT_EQ(r.remnant_id, 0u);
  (void)summary;
}

}  // namespace
}  // namespace kessler
