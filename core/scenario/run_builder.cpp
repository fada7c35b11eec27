// From a validated scenario to a ready-to-run Simulation: the population source, the propagator and the
// simulation parts.
#include "core/scenario/run_builder.hpp"

#include <exception>
#include <map>
#include <set>

#include "core/catalog/bundled_datasets.hpp"
#include "core/catalog/leo19647.hpp"
#include "core/catalog/state_table.hpp"
#include "core/catalog/synthetic.hpp"
#include "core/conjunctions/detector.hpp"
#include "core/decay/ballistic_fit.hpp"
#include "core/decay/run_atmosphere.hpp"
#include "core/integration/symplectic_propagator.hpp"
#include "core/physics/space_weather.hpp"
#include "core/scenario/breakup_validation.hpp"
#include "core/scenario/scenario_defaults.hpp"
#include "core/scenario/traffic_validation.hpp"
#include "core/sgp4/sgp4_propagator.hpp"

namespace kessler {
namespace {

// The population a scenario names and, for catalogs, the element sets SGP4 needs (by id).
struct LoadedPopulation {
  Population population;
  std::vector<ObjectId> element_ids;
  std::vector<MeanElements> elements;
  std::optional<IngestReport> report;  // when the population was ingested
};

IngestRules ingest_rules_of(const v1::PopulationSource& source) {
  const v1::IngestRules& r = source.rules();
  IngestRules rules;
  rules.strict = r.strict();
  if (r.has_min_perigee_km()) rules.min_perigee_km = r.min_perigee_km();
  if (r.has_max_apogee_km()) rules.max_apogee_km = r.max_apogee_km();
  rules.exclude_names.assign(r.exclude_names().begin(), r.exclude_names().end());
  rules.default_exclusions = !r.no_default_exclusions();
  rules.drop_docked = !r.keep_docked();
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

// Catalog ingests also leave out objects already below the scenario's burn-up altitude at the start (the
// same km value the simulation's configuration scales to metres).
IngestRules catalog_rules_of(const v1::Scenario& scenario) {
  IngestRules rules = ingest_rules_of(scenario.population());
  rules.burn_up_altitude_km = scenario.has_burn_up_altitude_km() ? scenario.burn_up_altitude_km()
                                                                 : scenario_defaults::kBurnUpAltitudeKm;
  return rules;
}

CatalogFormat catalog_format_of(v1::CatalogFormat format) {
  switch (format) {
    case v1::CATALOG_FORMAT_TLE:
      return CatalogFormat::kTle;
    case v1::CATALOG_FORMAT_OMM_CSV:
      return CatalogFormat::kOmmCsv;
    case v1::CATALOG_FORMAT_OMM_JSON:
      return CatalogFormat::kOmmJson;
    case v1::CATALOG_FORMAT_OMM_KVN:
      return CatalogFormat::kOmmKvn;
    default:
      return CatalogFormat::kDetect;
  }
}

// An ingest's outcome: refused (strict), nothing left (with the report's reasons), or the population.
std::optional<FieldError> take(IngestResult result, const std::string& path, LoadedPopulation& out) {
  out.report = result.report;
  if (result.refused) return FieldError{path, result.error};
  if (result.population.empty()) {
    std::string why = "no objects are left after the ingest filters (" +
                      std::to_string(result.report.records) + " records, " +
                      std::to_string(result.report.rejected) + " rejected";
    for (const auto& [reason, count] : result.report.filtered_by_reason)
      why += ", " + std::to_string(count) + " " + reason;
    return FieldError{"population", why + "); nothing to simulate"};
  }
  out.element_ids = result.population.id;
  out.elements = std::move(result.elements);
  out.population = std::move(result.population);
  return std::nullopt;
}

// Catalog objects' Cd A/m fitted in the run's own atmosphere to their observed decay (core/decay/), unless
// the scenario keeps the BSTAR rule, has no drag or propagates by SGP4 (whose drag is BSTAR itself).
void fit_drag(const v1::Scenario& scenario, const SimulationConfig& config,
              const BallisticFitSettings& settings, LoadedPopulation& out) {
  if (scenario.population().ballistic_coefficients() == v1::BALLISTIC_COEFFICIENTS_BSTAR) return;
  if (scenario.propagator() == v1::PROPAGATOR_SGP4) return;
  if (!config.force_model.drag || out.elements.size() != out.population.size()) return;
  BallisticFitCounts counts =
      fit_ballistic_coefficients(out.population, out.elements, config.start_epoch,
                                 run_atmosphere_density(config.force_model, config.start_epoch), settings);
  counts.atmosphere = run_atmosphere_name(config.force_model);
  if (out.report) out.report->drag_fit = counts;
}

// A bundled or inline catalog, ingested and its drag fitted.
std::optional<FieldError> ingest_and_fit(const CatalogInput& input, const std::string& path,
                                         const v1::Scenario& scenario, const SimulationConfig& config,
                                         const BuildOptions& options, LoadedPopulation& out) {
  if (auto e =
          take(ingest_catalog(input, catalog_rules_of(scenario), config.start_epoch, config.seed), path, out))
    return e;
  fit_drag(scenario, config, options.ballistic_fit, out);
  return std::nullopt;
}

std::optional<FieldError> load_population(const v1::Scenario& scenario, const SimulationConfig& config,
                                          const BuildOptions& options, LoadedPopulation& out) {
  const v1::PopulationSource& source = scenario.population();
  switch (source.source_case()) {
    case v1::PopulationSource::kDataset: {
      if (source.dataset() == "leo-19647") {
        out.population = load_leo19647(options.datasets_dir + "/leo-19647");
        return std::nullopt;
      }
      std::string why;
      auto input = load_bundled_catalog(source.dataset(), options.datasets_dir, &why);
      if (!input) return FieldError{"population.dataset", why};
      return ingest_and_fit(*input, "population.dataset", scenario, config, options, out);
    }
    case v1::PopulationSource::kCatalog: {
      CatalogInput input;
      input.format = catalog_format_of(source.catalog().format());
      input.text = source.catalog().text();
      input.source = "population.catalog.text";
      input.satcat_csv = source.catalog().satcat_csv();
      input.satcat_source = "population.catalog.satcat_csv";
      input.active_list = source.catalog().active_list();
      input.active_list_source = "population.catalog.active_list";
      return ingest_and_fit(input, "population.catalog", scenario, config, options, out);
    }
    case v1::PopulationSource::kSynthetic: {
      const v1::SyntheticPopulation& s = source.synthetic();
      SyntheticOptions o;
      o.objects = s.objects();
      if (s.has_active_fraction()) o.active_fraction = s.active_fraction();
      if (s.has_min_altitude_km()) o.min_altitude_km = s.min_altitude_km();
      if (s.has_max_altitude_km()) o.max_altitude_km = s.max_altitude_km();
      o.sizes = ingest_rules_of(source).sizes;
      try {
        out.population = generate_synthetic(o, config.seed);
      } catch (const std::invalid_argument& e) {
        return FieldError{"population.synthetic", e.what()};
      }
      return std::nullopt;
    }
    case v1::PopulationSource::kStateTable:
      return take(read_state_table(source.state_table(), ingest_rules_of(source), config.start_epoch,
                                   "population.state_table"),
                  "population.state_table", out);
    default:
      return FieldError{"population", "a population source is required"};
  }
}

std::optional<FieldError> make_parts(const v1::Scenario& scenario, const SimulationConfig& config,
                                     const LoadedPopulation* loaded, SimulationParts& parts) {
  if (scenario.propagator() == v1::PROPAGATOR_SGP4) {
    if (!loaded || loaded->elements.empty())
      return FieldError{"propagator", "sgp4 needs element sets: a catalog or a bundled catalog dataset"};
    try {
      parts.propagator =
          std::make_unique<Sgp4Propagator>(loaded->element_ids, loaded->elements, config.start_epoch);
    } catch (const std::invalid_argument& e) {
      return FieldError{"population", e.what()};
    }
  } else {
    auto propagator =
        std::make_unique<SymplecticPropagator>(config.force_model, config.start_epoch, config.integrator);
    propagator->set_threads(config.threads);
    parts.propagator = std::move(propagator);
  }
  if (config.conjunctions_enabled) {
    if (auto problem = ConjunctionDetector::validate(config.conjunctions, config.dt_s)) {
      std::string path = "conjunctions";
      if (problem->rfind("kappa_max", 0) == 0) path = "conjunctions.kappa_max";
      if (problem->rfind("screening_distance_m", 0) == 0) path = "conjunctions.screening_distance_km";
      if (problem->rfind("dt_s", 0) == 0) path = "dt_s";
      return FieldError{path, *problem};
    }
    parts.scanner = make_detector_scanner(config.conjunctions);
  }
  return std::nullopt;
}

// The core's configuration with the traffic's launches (read from their files); errors: unreadable
// sources of launches.
std::optional<FieldError> config_of(const v1::Scenario& scenario, const BuildOptions& options,
                                    SimulationConfig& config) {
  config = to_simulation_config(scenario, options.threads);
  if (auto e = traffic_launches_of(scenario, config, {options.traffic_dir, options.datasets_dir},
                                   config.traffic.launches))
    return e;
  if (config.force_model.atmosphere == AtmosphereModel::kNrlmsise00 &&
      config.force_model.solar_activity.mode != SolarActivityMode::kConstant) {
    try {
      config.force_model.space_weather = SpaceWeather::in_datasets(options.datasets_dir);
    } catch (const std::exception& e) {
      return FieldError{"force_model.solar_activity", e.what()};
    }
  }
  if (!options.checkpoints) {
    config.checkpoint_every_steps = 0;
    config.checkpoint_every_wall_s = 0.0;
  }
  if (options.adjust_config) options.adjust_config(config);
  return std::nullopt;
}

// Loader exceptions (missing files, unsound objects) become errors of the population.
std::optional<FieldError> load_guarded(const v1::Scenario& scenario, const SimulationConfig& config,
                                       const BuildOptions& options, LoadedPopulation& loaded) {
  try {
    return load_population(scenario, config, options, loaded);
  } catch (const std::exception& e) {
    return FieldError{"population", e.what()};
  }
}

}  // namespace

std::unique_ptr<Simulation> build_simulation(const v1::Scenario& scenario, const BuildOptions& options,
                                             FieldError* error, std::optional<IngestReport>* ingest) {
  FieldError ignored;
  if (!error) error = &ignored;
  auto fail = [&](FieldError e) {
    *error = std::move(e);
    return nullptr;
  };
  if (auto e = validate_scenario(scenario)) return fail(*e);
  SimulationConfig config;
  if (auto e = config_of(scenario, options, config)) return fail(*e);
  LoadedPopulation loaded;
  auto load_error = load_guarded(scenario, config, options, loaded);
  if (ingest) *ingest = loaded.report;
  if (load_error) return fail(*load_error);
  Population& population = loaded.population;
  const auto& source = scenario.population();
  if (source.has_max_objects() && population.size() > source.max_objects()) {
    std::vector<char> drop(population.size(), 0);
    for (std::size_t i = source.max_objects(); i < drop.size(); ++i) drop[i] = 1;
    population.remove_flagged(drop);
  }
  if (population.empty())
    return fail({"population", "no objects are left after the ingest filters; nothing to simulate"});
  if (auto problem = population.validate()) return fail({"population", *problem});
  // Scheduled breakups name objects by id: only the ingested population says whether they exist.
  if (auto e = check_breakups_against_population(config.breakups, population)) return fail(*e);
  SimulationParts parts;
  if (auto e = make_parts(scenario, config, &loaded, parts)) return fail(*e);
  if (options.adjust_parts) options.adjust_parts(config, parts);
  return std::make_unique<Simulation>(config, std::move(population), std::move(parts));
}

std::unique_ptr<Simulation> resume_simulation(const v1::Scenario& scenario, const std::string& checkpoint,
                                              const BuildOptions& options, FieldError* error) {
  FieldError ignored;
  if (!error) error = &ignored;
  auto fail = [&](FieldError e) {
    *error = std::move(e);
    return nullptr;
  };
  if (auto e = validate_scenario(scenario)) return fail(*e);
  SimulationConfig config;
  if (auto e = config_of(scenario, options, config)) return fail(*e);
  // The checkpoint holds the population; SGP4 alone needs the element sets again.
  LoadedPopulation loaded;
  if (scenario.propagator() == v1::PROPAGATOR_SGP4)
    if (auto e = load_guarded(scenario, config, options, loaded)) return fail(*e);
  SimulationParts parts;
  if (auto e = make_parts(scenario, config, &loaded, parts)) return fail(*e);
  if (options.adjust_parts) options.adjust_parts(config, parts);
  try {
    return Simulation::resume(config, checkpoint, std::move(parts));
  } catch (const std::exception& e) {
    return fail({"checkpoint", e.what()});
  }
}

IngestOutcome ingest_outcome(const IngestReport& report) {
  IngestOutcome out;
  out.records = report.records;
  out.kept = report.kept;
  if (report.drag_fit) {
    out.drag = {{"fitted from the mean-motion derivative", report.drag_fit->from_mean_motion_derivative},
                {"fitted from SGP4's BSTAR decay", report.drag_fit->from_sgp4_bstar},
                {"no decay signal: ingest rule", report.drag_fit->no_signal}};
  } else {
    out.drag = {{"BSTAR rule", report.drag_from_bstar}, {"Cd and size", report.drag_from_size}};
  }
  for (const auto& [reason, count] : report.rejected_by_reason)
    out.dropped.push_back({"rejected: " + reason, count});
  // propagation_failures also lists objects whose state came out invalid ("invalid state", counted
  // apart): only messages that are SGP4 errors are split out of "SGP4 failed".
  std::set<std::string> sgp4_errors;
  for (Sgp4Error e : {Sgp4Error::kMeanEccentricity, Sgp4Error::kMeanMotion, Sgp4Error::kPerturbedEccentricity,
                      Sgp4Error::kSemiLatusRectum, Sgp4Error::kDecayed})
    sgp4_errors.insert(sgp4_error_text(e));
  std::map<std::string, std::uint64_t> by_error;
  for (const auto& [id, message] : report.propagation_failures)
    if (sgp4_errors.count(message)) ++by_error[message];
  for (const auto& [reason, count] : report.filtered_by_reason) {
    if (reason != "SGP4 failed") {
      out.dropped.push_back({reason, count});
      continue;
    }
    std::uint64_t listed = 0;
    for (const auto& [message, n] : by_error) {
      out.dropped.push_back({"SGP4 failed: " + message, n});
      listed += n;
    }
    if (count > listed) out.dropped.push_back({reason, count - listed});
  }
  return out;
}

}  // namespace kessler
