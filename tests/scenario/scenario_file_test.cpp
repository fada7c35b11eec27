// Scenario files: good and bad ones, with the exact messages a user sees.
#include <gtest/gtest.h>

#include <filesystem>

#include "core/scenario/run_builder.hpp"
#include "tests/scenario/verdict_table.hpp"

namespace kessler {
namespace {

// "" expected: the text parses and validates.
using Case = test::VerdictCase;

const Case kCases[] = {
    {"minimal", "population: {dataset: leo-19647}", ""},
    {"minimal json", R"({"population": {"synthetic": {"objects": 100}}})", ""},
    {"full",
     R"(name: full
start_epoch: "2022-01-22T00:00:00Z"
duration_days: 7
dt_s: 5
propagator: numerical
integrator: yoshida4
force_model: {kepler: true, j2: true, c22_s22: true, drag: true, srp: false, atmosphere: exponential_fit}
population:
  dataset: catalog-2022
  rules: {min_perigee_km: 200, max_apogee_km: 1800, exclude_names: ["STARLINK*"], object_types: [DEBRIS]}
  max_objects: 500
conjunctions: {enabled: true, narrow_phase: linear, kappa_max: 5, active_pairs_evade: false}
burn_up_altitude_km: 140
checkpoints: {every_steps: 100, every_wall_s: 30}
progress_every_steps: 50
seed: 42
)",
     ""},
    {"protobuf json names", R"({"durationDays": 2, "dtS": 5, "seed": "42", "progressEverySteps": "10",
        "population": {"dataset": "leo-19647", "maxObjects": "100"}})",
     ""},
    {"end epoch", "end_epoch: 2022-03-02T00:00:00Z\npopulation: {dataset: leo-19647}", ""},
    {"leo-19647 epoch", "start_epoch: 2022-01-01T00:00:00Z\npopulation: {dataset: leo-19647}",
     "start_epoch: must be the leo-19647 states' epoch, 2022-03-01T00:00:00Z (or left out)"},
    {"full enum names", "propagator: PROPAGATOR_SGP4\npopulation: {dataset: catalog-2022}", ""},
    {"empty", "", "the scenario is empty (it needs at least a population)"},
    {"no population", "name: x",
     "population: a population source is required (dataset, catalog, synthetic or state_table)"},
    {"malformed", "population: {dataset: leo-19647}\n  seed: 2\n",
     "not valid YAML or JSON: line 2, column 3: end of map not found"},
    {"not a mapping", "- a\n- b", "expected a mapping of keys, got a list"},
    {"unknown key", "populaton: {dataset: leo-19647}",
     "populaton: unknown key (known keys here: name, start_epoch, duration_days, end_epoch, dt_s, "
     "propagator, "
     "integrator, force_model, population, conjunctions, burn_up_altitude_km, checkpoints, "
     "progress_every_steps, "
     "seed, breakups, traffic, ensemble, snapshots)"},
    {"unknown nested key", "population: {dataset: leo-19647}\nconjunctions: {kappa: 3}",
     "conjunctions.kappa: unknown key (known keys here: enabled, narrow_phase, kappa_max, "
     "screening_distance_km, "
     "active_pairs_evade, active_passive_max_passive_radius_m, active_passive_evasion_efficiency)"},
    {"nrlmsise00 constant",
     "population: {dataset: leo-19647}\nforce_model: {atmosphere: nrlmsise00, "
     "solar_activity: {mode: constant, f107_sfu: 200, ap: 12}}",
     ""},
    {"nrlmsise00 cycle",
     "population: {dataset: leo-19647}\nforce_model: {atmosphere: nrlmsise00, "
     "solar_activity: {mode: cycle}}",
     ""},
    {"solar activity without nrlmsise00",
     "population: {dataset: leo-19647}\nforce_model: {solar_activity: "
     "{mode: cycle}}",
     "force_model.solar_activity: only the nrlmsise00 atmosphere reads solar activity"},
    {"f107 out of range",
     "population: {dataset: leo-19647}\nforce_model: {atmosphere: nrlmsise00, "
     "solar_activity: {mode: constant, f107_sfu: -3}}",
     "force_model.solar_activity.f107_sfu: must be in (0, 1000] sfu, got -3"},
    {"ap out of range",
     "population: {dataset: leo-19647}\nforce_model: {atmosphere: nrlmsise00, "
     "solar_activity: {mode: constant, ap: 500}}",
     "force_model.solar_activity.ap: must be in [0, 400], got 500"},
    {"fixed values need the constant mode",
     "population: {dataset: leo-19647}\nforce_model: {atmosphere: "
     "nrlmsise00, solar_activity: {mode: observed, ap: 5}}",
     "force_model.solar_activity.ap: only the constant mode takes fixed values"},
    {"evasion efficiency",
     "population: {dataset: leo-19647}\nconjunctions: {active_passive_evasion_efficiency: 1.5}",
     "conjunctions.active_passive_evasion_efficiency: must be in [0, 1], got 1.5"},
    {"number as text", "dt_s: ten\npopulation: {dataset: leo-19647}", "dt_s: expected a number, got 'ten'"},
    {"quoted number", "{\"dt_s\": \"10\", \"population\": {\"dataset\": \"leo-19647\"}}",
     "dt_s: expected a number, got the string '10'"},
    {"bool", "population: {dataset: leo-19647}\nforce_model: {drag: maybe}",
     "force_model.drag: expected true or false, got 'maybe'"},
    {"negative count", "population: {synthetic: {objects: -5}}",
     "population.synthetic.objects: must not be negative"},
    {"fractional count", "population: {synthetic: {objects: 2.5}}",
     "population.synthetic.objects: expected a whole number, got '2.5'"},
    {"enum", "propagator: kepler\npopulation: {dataset: leo-19647}",
     "propagator: unknown value 'kepler' (expected one of: numerical, sgp4)"},
    {"drag coupling", "population: {dataset: leo-19647}\nforce_model: {drag_coupling: step_ends}", ""},
    {"unknown drag coupling", "population: {dataset: leo-19647}\nforce_model: {drag_coupling: midpoint}",
     "force_model.drag_coupling: unknown value 'midpoint' (expected one of: every_kick, step_ends)"},
    {"list expected", "population: {dataset: leo-19647, rules: {exclude_names: STARLINK*}}",
     "population.rules.exclude_names: expected a list, got 'STARLINK*'"},
    {"mapping expected", "population: leo-19647", "population: expected a mapping of keys, got 'leo-19647'"},
    {"no value", "dt_s:\npopulation: {dataset: leo-19647}", "dt_s: has no value"},
    {"two sources", "population: {dataset: leo-19647, synthetic: {objects: 3}}",
     "population.synthetic: conflicts with 'dataset': give only one of them"},
    {"duration and end",
     "duration_days: 1\nend_epoch: 2022-03-03T00:00:00Z\npopulation: {dataset: leo-19647}",
     "end_epoch: conflicts with 'duration_days': give only one of them"},
    {"zero step", "dt_s: 0\npopulation: {dataset: leo-19647}", "dt_s: must be positive, got 0"},
    {"negative step", "dt_s: -10\npopulation: {dataset: leo-19647}", "dt_s: must be positive, got -10"},
    {"shorter than a step", "duration_days: 0.0001\npopulation: {dataset: leo-19647}",
     "duration_days: the run (8.64 s) is shorter than one step (dt_s = 30 s)"},
    {"end before start", "end_epoch: 2021-12-31T00:00:00Z\npopulation: {dataset: catalog-2022}",
     "end_epoch: must be after start_epoch"},
    {"bad epoch", "start_epoch: yesterday\npopulation: {dataset: catalog-2022}",
     "start_epoch: not an ISO 8601 UTC date (expected YYYY-MM-DD): 'yesterday'"},
    {"kappa zero", "population: {dataset: leo-19647}\nconjunctions: {kappa_max: 0}",
     "conjunctions.kappa_max: must be in (0, 10], got 0"},
    {"kappa too big", "population: {dataset: leo-19647}\nconjunctions: {kappa_max: 12}",
     "conjunctions.kappa_max: must be in (0, 10], got 12"},
    {"screening", "population: {dataset: leo-19647}\nconjunctions: {screening_distance_km: -1}",
     "conjunctions.screening_distance_km: must be positive, got -1"},
    {"unknown dataset", "population: {dataset: leo-2000}",
     "population.dataset: unknown dataset 'leo-2000' (available: catalog-2022, catalog-2019, leo-19647)"},
    {"empty catalog", "population: {catalog: {format: tle, text: \"\"}}",
     "population.catalog.text: is empty"},
    {"no objects", "population: {synthetic: {objects: 0}}",
     "population.synthetic.objects: must be at least 1"},
    {"altitude band", "population: {synthetic: {objects: 10, min_altitude_km: 900, max_altitude_km: 800}}",
     "population.synthetic.max_altitude_km: must be above min_altitude_km (900 km), got 800 km"},
    {"perigee band", "population: {dataset: catalog-2022, rules: {min_perigee_km: 2500}}",
     "population.rules.max_apogee_km: must be above min_perigee_km (2500 km), got 2000 km"},
    {"object type", "population: {dataset: catalog-2022, rules: {object_types: [DEBRIS, ROCKET]}}",
     "population.rules.object_types[1]: unknown object type 'ROCKET' (expected one of: PAYLOAD, ROCKET BODY, "
     "DEBRIS, UNKNOWN)"},
    {"sgp4 without elements", "propagator: sgp4\npopulation: {synthetic: {objects: 10}}",
     "propagator: sgp4 needs element sets: a catalog or a bundled catalog dataset"},
    {"fitted drag without elements", "population: {dataset: leo-19647, ballistic_coefficients: fitted}",
     "population.ballistic_coefficients: fitted needs element sets (their observed decay): a catalog or a "
     "bundled catalog dataset"},
    {"unknown drag rule", "population: {dataset: catalog-2022, ballistic_coefficients: measured}",
     "population.ballistic_coefficients: unknown value 'measured' (expected one of: fitted, bstar)"},
    {"burn-up", "burn_up_altitude_km: -5\npopulation: {dataset: leo-19647}",
     "burn_up_altitude_km: must be in [0, 2000), got -5"},
    {"progress", "progress_every_steps: 0\npopulation: {dataset: leo-19647}",
     "progress_every_steps: must be at least 1"},
    {"checkpoint wall", "checkpoints: {every_wall_s: -1}\npopulation: {dataset: leo-19647}",
     "checkpoints.every_wall_s: must not be negative, got -1"},
    {"snapshots", "snapshots: {every_days: -1}\npopulation: {dataset: leo-19647}",
     "snapshots.every_days: must not be negative, got -1"},
    {"max objects", "population: {dataset: leo-19647, max_objects: 0}",
     "population.max_objects: must be at least 1 (leave it out for all objects)"},
};

class ScenarioFiles : public ::testing::TestWithParam<Case> {};

TEST_P(ScenarioFiles, GiveTheExpectedVerdict) {
  test::expect_verdict(GetParam());
}

INSTANTIATE_TEST_SUITE_P(Table, ScenarioFiles, ::testing::ValuesIn(kCases), test::VerdictCaseName());

TEST(ScenarioMapping, IntegratorNamesMapOntoTheCompositions) {
  v1::Scenario s;
  ASSERT_FALSE(parse_scenario("population: {synthetic: {objects: 5}}\nintegrator: yoshida4", s));
  EXPECT_EQ(to_simulation_config(s).integrator, Integrator::kYoshida4);
  ASSERT_FALSE(parse_scenario("population: {synthetic: {objects: 5}}\nintegrator: blanes_moan4", s));
  EXPECT_EQ(to_simulation_config(s).integrator, Integrator::kBlanesMoan4);
  auto error = parse_scenario("population: {synthetic: {objects: 5}}\nintegrator: rk4", s);
  ASSERT_TRUE(error);
  EXPECT_EQ(error->path, "integrator");
}

TEST(ScenarioMapping, TheSolarCycleAtmosphereAndTheEvasionEfficiencyReachTheCore) {
  v1::Scenario s;
  ASSERT_FALSE(
      parse_scenario("population: {synthetic: {objects: 5}}\nforce_model: {atmosphere: nrlmsise00, "
                     "solar_activity: {mode: constant, f107_sfu: 210, ap: 7}}\n"
                     "conjunctions: {active_passive_evasion_efficiency: 0.8}",
                     s));
  SimulationConfig c = to_simulation_config(s);
  EXPECT_EQ(c.force_model.atmosphere, AtmosphereModel::kNrlmsise00);
  EXPECT_EQ(c.force_model.solar_activity.mode, SolarActivityMode::kConstant);
  EXPECT_EQ(c.force_model.solar_activity.f107_sfu, 210.0);
  EXPECT_EQ(c.force_model.solar_activity.ap, 7.0);
  EXPECT_EQ(c.conjunctions.active_passive_evasion_efficiency, 0.8);
  ASSERT_FALSE(
      parse_scenario("population: {synthetic: {objects: 5}}\nforce_model: {atmosphere: nrlmsise00}", s));
  c = to_simulation_config(s);
  EXPECT_EQ(c.force_model.solar_activity.mode, SolarActivityMode::kObserved);
  EXPECT_EQ(c.conjunctions.active_passive_evasion_efficiency, 1.0);
}

// Every default is the paper's but the integrator and its step: Blanes-Moan at 30 s, more exact and
// faster than the paper's Yoshida at 10 s (tests/physics/integrator_test.cpp).
TEST(ScenarioMapping, DefaultsAreThePapersButTheIntegrator) {
  v1::Scenario s;
  ASSERT_FALSE(parse_scenario("population: {synthetic: {objects: 5}}", s));
  SimulationConfig c = to_simulation_config(s);
  EXPECT_EQ(c.start_epoch, UtcEpoch::from_calendar(2022, 1, 1, 0, 0, 0.0));
  EXPECT_EQ(c.dt_s, 30.0);
  EXPECT_EQ(c.integrator, Integrator::kBlanesMoan4);
  EXPECT_EQ(c.duration_s, 86400.0);
  EXPECT_EQ(c.burn_up_altitude_m, 150e3);
  EXPECT_EQ(c.conjunctions.kappa_max, 10.0);
  EXPECT_EQ(c.conjunctions.screening_distance_m, 0.0);
  EXPECT_EQ(c.conjunctions.narrow_phase, NarrowPhase::kHermite);
  EXPECT_TRUE(c.conjunctions.active_pairs_evade);
  EXPECT_EQ(c.conjunctions.active_passive_max_passive_radius_m, 0.10);
  EXPECT_TRUE(c.force_model.kepler && c.force_model.j2 && c.force_model.c22_s22 && c.force_model.drag &&
              c.force_model.srp && c.force_model.srp_earth_shadow);
  EXPECT_EQ(c.force_model.atmosphere, AtmosphereModel::kDensityTable);
  EXPECT_TRUE(c.conjunctions_enabled);
  EXPECT_EQ(c.checkpoint_every_steps, 2880 / 50);
  EXPECT_EQ(c.checkpoint_every_wall_s, 60.0);
  EXPECT_EQ(c.seed, 1u);
}

TEST(ScenarioMapping, SetFieldsReachTheConfig) {
  v1::Scenario s;
  ASSERT_FALSE(parse_scenario(R"(
start_epoch: 2022-03-01T00:00:00Z
end_epoch: 2022-03-08T00:00:00Z
dt_s: 5
force_model: {srp: false, atmosphere: exponential_fit}
population: {dataset: leo-19647}
conjunctions: {screening_distance_km: 5, narrow_phase: linear, enabled: false}
burn_up_altitude_km: 120
checkpoints: {every_steps: 0}
seed: 9
)",
                              s));
  ASSERT_FALSE(validate_scenario(s));
  SimulationConfig c = to_simulation_config(s, 3);
  EXPECT_EQ(c.duration_s, 7 * 86400.0);
  EXPECT_EQ(c.dt_s, 5.0);
  EXPECT_FALSE(c.force_model.srp);
  EXPECT_EQ(c.force_model.atmosphere, AtmosphereModel::kExponentialFit);
  EXPECT_EQ(c.conjunctions.screening_distance_m, 5000.0);
  EXPECT_EQ(c.conjunctions.narrow_phase, NarrowPhase::kLinear);
  EXPECT_FALSE(c.conjunctions_enabled);
  EXPECT_EQ(c.burn_up_altitude_m, 120e3);
  EXPECT_EQ(c.checkpoint_every_steps, 0);
  EXPECT_EQ(c.seed, 9u);
  EXPECT_EQ(c.threads, 3);
}

TEST(ScenarioFilesShipped, AllParseAndValidate) {
  int count = 0;
  for (const auto& entry : std::filesystem::directory_iterator(KESSLER_SCENARIOS_DIR)) {
    if (entry.path().extension() != ".yaml" && entry.path().extension() != ".json") continue;
    v1::Scenario s;
    auto error = load_scenario_file(entry.path().string(), s);
    if (!error) error = validate_scenario(s);
    EXPECT_FALSE(error) << entry.path() << ": " << error->message();
    ++count;
  }
  EXPECT_GE(count, 4);
}

TEST(ScenarioFilesShipped, AMissingFileIsAClearError) {
  v1::Scenario s;
  auto error = load_scenario_file("/nonexistent/x.yaml", s);
  ASSERT_TRUE(error);
  EXPECT_EQ(error->message(),
            "scenario file '/nonexistent/x.yaml' cannot be read (No such file or directory)");
}

}  // namespace
}  // namespace kessler
