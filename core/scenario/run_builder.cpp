// From a validated scenario to a ready-to-run Simulation: the population source, the propagator and the
// simulation parts. Pieces built on other branches are wired as they land (the __has_include guards
// keep this file building until then, and go once every piece is in).
#include "core/scenario/run_builder.hpp"

#include <exception>

#if __has_include("core/integration/yoshida_propagator.hpp")
#define KESSLER_HAVE_NUMERICAL 1
#include "core/integration/yoshida_propagator.hpp"
#endif
#if __has_include("core/conjunctions/closest_encounters.hpp")
#define KESSLER_HAVE_DETECTOR 1
#include "core/conjunctions/detector.hpp"
#endif
#if __has_include("core/population/leo19647.hpp")
#define KESSLER_HAVE_LEO19647 1
#include "core/population/leo19647.hpp"
#endif

namespace kessler {
namespace {

FieldError not_built(const std::string& path, const std::string& what) {
  return FieldError{path, what + " is not part of this build"};
}

// The population the scenario names, before max_objects.
std::optional<FieldError> load_population(const v1::Scenario& scenario, const SimulationConfig& config,
                                          const BuildOptions& options, Population& out) {
  (void)config;
  (void)options;
  (void)out;
  const v1::PopulationSource& source = scenario.population();
  try {
    switch (source.source_case()) {
      case v1::PopulationSource::kDataset:
        if (source.dataset() == "leo-19647") {
#ifdef KESSLER_HAVE_LEO19647
          out = load_leo19647(options.datasets_dir + "/leo-19647");
          return std::nullopt;
#else
          return not_built("population.dataset", "the leo-19647 loader");
#endif
        }
        return not_built("population.dataset", "the catalog-2022 loader");
      case v1::PopulationSource::kCatalog:
        return not_built("population.catalog", "catalog ingest");
      case v1::PopulationSource::kSynthetic:
        return not_built("population.synthetic", "the synthetic generator");
      case v1::PopulationSource::kStateTable:
        return not_built("population.state_table", "the state-table reader");
      default:
        return FieldError{"population", "a population source is required"};
    }
  } catch (const std::exception& e) {
    return FieldError{"population", e.what()};
  }
}

std::optional<FieldError> make_parts(const v1::Scenario& scenario, const SimulationConfig& config,
                                     SimulationParts& parts) {
  (void)parts;
  if (scenario.propagator() == v1::PROPAGATOR_SGP4) return not_built("propagator", "the sgp4 propagator");
#ifdef KESSLER_HAVE_NUMERICAL
  auto propagator = std::make_unique<YoshidaPropagator>(config.force_model, config.start_epoch);
  propagator->set_threads(config.threads);
  parts.propagator = std::move(propagator);
  parts.find_burn_ups = &find_burn_ups;
#else
  return not_built("propagator", "the numerical propagator");
#endif
  if (config.conjunctions_enabled) {
#ifdef KESSLER_HAVE_DETECTOR
    if (auto problem = ConjunctionDetector::validate(config.conjunctions, config.dt_s)) {
      std::string path = "conjunctions";
      if (problem->rfind("kappa_max", 0) == 0) path = "conjunctions.kappa_max";
      if (problem->rfind("screening_distance_m", 0) == 0) path = "conjunctions.screening_distance_km";
      if (problem->rfind("dt_s", 0) == 0) path = "dt_s";
      return FieldError{path, *problem};
    }
    parts.scanner = make_detector_scanner(config.conjunctions);
#else
    return not_built("conjunctions", "conjunction detection");
#endif
  }
  return std::nullopt;
}

std::optional<FieldError> prepare(const v1::Scenario& scenario, const BuildOptions& options,
                                  SimulationConfig& config, SimulationParts& parts) {
  if (auto e = validate_scenario(scenario)) return e;
  config = to_simulation_config(scenario, options.threads);
  if (!options.checkpoints) {
    config.checkpoint_every_steps = 0;
    config.checkpoint_every_wall_s = 0.0;
  }
  return make_parts(scenario, config, parts);
}

}  // namespace

std::unique_ptr<Simulation> build_simulation(const v1::Scenario& scenario, const BuildOptions& options,
                                             FieldError* error) {
  FieldError ignored;
  if (!error) error = &ignored;
  SimulationConfig config;
  SimulationParts parts;
  if (auto e = prepare(scenario, options, config, parts)) {
    *error = *e;
    return nullptr;
  }
  Population population;
  if (auto e = load_population(scenario, config, options, population)) {
    *error = *e;
    return nullptr;
  }
  const auto& source = scenario.population();
  if (source.has_max_objects() && population.size() > source.max_objects()) {
    std::vector<char> drop(population.size(), 0);
    for (std::size_t i = source.max_objects(); i < drop.size(); ++i) drop[i] = 1;
    population.remove_flagged(drop);
  }
  if (population.empty()) {
    *error = FieldError{"population", "no objects are left after the ingest filters; nothing to simulate"};
    return nullptr;
  }
  if (auto problem = population.validate()) {
    *error = FieldError{"population", *problem};
    return nullptr;
  }
  return std::make_unique<Simulation>(config, std::move(population), std::move(parts));
}

std::unique_ptr<Simulation> resume_simulation(const v1::Scenario& scenario, const std::string& checkpoint,
                                              const BuildOptions& options, FieldError* error) {
  FieldError ignored;
  if (!error) error = &ignored;
  SimulationConfig config;
  SimulationParts parts;
  if (auto e = prepare(scenario, options, config, parts)) {
    *error = *e;
    return nullptr;
  }
  try {
    return Simulation::resume(config, checkpoint, std::move(parts));
  } catch (const std::exception& e) {
    *error = FieldError{"checkpoint", e.what()};
    return nullptr;
  }
}

}  // namespace kessler
