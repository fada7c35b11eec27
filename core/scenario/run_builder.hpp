// From a scenario (file text or proto message) to a ready-to-run Simulation: parsing, validation with
// field paths, population ingest, propagator choice. What the CLI's run --local and the daemon share.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/catalog/ingest.hpp"
#include "core/decay/ballistic_fit.hpp"
#include "core/simulation/simulation.hpp"
#include "kessler/v1/scenario.pb.h"

namespace kessler {

// A problem with a scenario: the field's path ("conjunctions.kappa_max", "population.catalog.text line
// 12") and the reason.
struct FieldError {
  std::string path;
  std::string reason;
  std::string message() const { return path.empty() ? reason : path + ": " + reason; }
};

// YAML or JSON text onto the message. Unknown keys, wrong types and malformed text are errors.
std::optional<FieldError> parse_scenario(std::string_view text, v1::Scenario& out);

// A scenario file (YAML or JSON) read and parsed; a file that cannot be read is an error too.
std::optional<FieldError> load_scenario_file(const std::string& path, v1::Scenario& out);

// Range and consistency checks of every field, before anything runs.
std::optional<FieldError> validate_scenario(const v1::Scenario& scenario);

// The core's configuration of a valid scenario, unset fields at the paper's defaults
// (core/scenario/scenario_defaults.hpp). traffic.launches stays empty: the launches' sources are files
// (shipped plans, the bundled catalog), which build_simulation and resume_simulation read
// (traffic_validation.hpp, traffic_launches_of).
SimulationConfig to_simulation_config(const v1::Scenario& scenario, int threads = 0);

struct BuildOptions {
  int threads = 0;  // 0: OpenMP's default
  std::string datasets_dir = KESSLER_DATASETS_DIR;
  // Where the shipped launch plans (traffic.plans) live: <traffic_dir>/<name>.csv.
  std::string traffic_dir = KESSLER_TRAFFIC_DIR;
  // False: no checkpoints are taken (a host with nowhere to keep them saves the time).
  bool checkpoints = true;
  // How catalog objects' ballistic coefficients are fitted (population.ballistic_coefficients: fitted).
  BallisticFitSettings ballistic_fit;
  // Applied to the core configuration after the scenario's, for fresh and resumed runs alike (hosts
  // and tests: settings no scenario field reaches). Empty: none.
  std::function<void(SimulationConfig&)> adjust_config;
  // Applied to the parts built for the scenario (propagator, scanner), for fresh and resumed runs alike:
  // a host may wrap or replace them (core/distributed/ shares their work among MPI ranks). Empty: none.
  std::function<void(const SimulationConfig&, SimulationParts&)> adjust_parts;
};

// The run the scenario describes: validates, ingests the population, builds the propagator.
// Returns nullptr with *error set when the scenario cannot run (an empty population after filters too).
// `ingest`, when given, receives the ingest's report for a population read from a catalog, a bundled
// catalog or a state table (also when the ingest leaves nothing to run); it stays empty for synthetic
// populations and the leo-19647 dataset, which are not ingested.
std::unique_ptr<Simulation> build_simulation(const v1::Scenario& scenario, const BuildOptions& options,
                                             FieldError* error,
                                             std::optional<IngestReport>* ingest = nullptr);

// What an ingest did with a catalog, in a user's terms: each record is kept or dropped for exactly one
// reason, so records == kept + the sum of `dropped`.
struct IngestOutcome {
  std::uint64_t records = 0;
  std::uint64_t kept = 0;
  // Reason and count, in the report's order: bad records as "rejected: <reason>", the filters' reasons
  // ("docked", "excluded name", ...), and SGP4 failures by their error as "SGP4 failed: <error>".
  std::vector<std::pair<std::string, std::uint64_t>> dropped;
  // How the kept objects' Cd A/m was set: source and count (each kept object once).
  std::vector<std::pair<std::string, std::uint64_t>> drag;
};
IngestOutcome ingest_outcome(const IngestReport& report);

// The same run continued from a checkpoint taken by it.
std::unique_ptr<Simulation> resume_simulation(const v1::Scenario& scenario, const std::string& checkpoint,
                                              const BuildOptions& options, FieldError* error);

}  // namespace kessler
