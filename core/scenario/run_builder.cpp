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
#if __has_include("core/population/bundled_datasets.hpp")
#define KESSLER_HAVE_INGEST 1
#include "core/population/bundled_datasets.hpp"
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

#ifdef KESSLER_HAVE_INGEST
IngestRules ingest_rules_of(const v1::PopulationSource& source) {
  const v1::IngestRules& r = source.rules();
  IngestRules rules;
  rules.strict = r.strict();
  if (r.has_min_perigee_km()) rules.min_perigee_km = r.min_perigee_km();
  if (r.has_max_apogee_km()) rules.max_apogee_km = r.max_apogee_km();
  rules.exclude_names.assign(r.exclude_names().begin(), r.exclude_names().end());
  rules.default_exclusions = !r.no_default_exclusions();
  rules.object_types.assign(r.object_types().begin(), r.object_types().end());
  if (r.has_max_epoch_after_start_days()) rules.max_epoch_after_start_days = r.max_epoch_after_start_days();
  if (r.has_small_radius_mean_m()) rules.sizes.small.mean_m = r.small_radius_mean_m();
  if (r.has_small_radius_stddev_m()) rules.sizes.small.stddev_m = r.small_radius_stddev_m();
  if (r.has_medium_radius_mean_m()) rules.sizes.medium.mean_m = r.medium_radius_mean_m();
  if (r.has_medium_radius_stddev_m()) rules.sizes.medium.stddev_m = r.medium_radius_stddev_m();
  if (r.has_large_radius_mean_m()) rules.sizes.large.mean_m = r.large_radius_mean_m();
  if (r.has_large_radius_stddev_m()) rules.sizes.large.stddev_m = r.large_radius_stddev_m();
  rules.max_objects = source.has_max_objects() ? source.max_objects() : 0;
  return rules;
}

CatalogFormat catalog_format_of(v1::CatalogFormat format) {
  switch (format) {
    case v1::CATALOG_FORMAT_TLE: return CatalogFormat::kTle;
    case v1::CATALOG_FORMAT_OMM_CSV: return CatalogFormat::kOmmCsv;
    case v1::CATALOG_FORMAT_OMM_JSON: return CatalogFormat::kOmmJson;
    case v1::CATALOG_FORMAT_OMM_KVN: return CatalogFormat::kOmmKvn;
    default: return CatalogFormat::kDetect;
  }
}

// A catalog through the paper's ingest rules; the report's reasons when nothing is left.
std::optional<FieldError> ingest(const CatalogInput& input, const v1::PopulationSource& source,
                                 const SimulationConfig& config, const std::string& path, Population& out) {
  IngestResult result = ingest_catalog(input, ingest_rules_of(source), config.start_epoch, config.seed);
  if (result.refused) return FieldError{path, result.error};
  if (result.population.empty()) {
    std::string why = "no objects are left after the ingest filters (" + std::to_string(result.report.records) +
                      " records, " + std::to_string(result.report.rejected) + " rejected";
    for (const auto& [reason, count] : result.report.filtered_by_reason)
      why += ", " + std::to_string(count) + " " + reason;
    return FieldError{"population", why + "); nothing to simulate"};
  }
  out = std::move(result.population);
  return std::nullopt;
}
#endif

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
#ifdef KESSLER_HAVE_INGEST
        {
          std::string why;
          auto input = load_bundled_catalog(source.dataset(), options.datasets_dir, &why);
          if (!input) return FieldError{"population.dataset", why};
          return ingest(*input, source, config, "population.dataset", out);
        }
#else
        return not_built("population.dataset", "the catalog-2022 loader");
#endif
      case v1::PopulationSource::kCatalog: {
#ifdef KESSLER_HAVE_INGEST
        CatalogInput input;
        input.format = catalog_format_of(source.catalog().format());
        input.text = source.catalog().text();
        input.source = "population.catalog.text";
        input.satcat_csv = source.catalog().satcat_csv();
        input.satcat_source = "population.catalog.satcat_csv";
        input.active_list = source.catalog().active_list();
        input.active_list_source = "population.catalog.active_list";
        return ingest(input, source, config, "population.catalog", out);
#else
        return not_built("population.catalog", "catalog ingest");
#endif
      }
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
