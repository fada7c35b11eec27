// From a scenario (file text or proto message) to a ready-to-run Simulation: parsing, validation with
// field paths, population ingest, propagator choice. What the CLI's run --local and the daemon share.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <string_view>

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
// (core/scenario/scenario_defaults.hpp).
SimulationConfig to_simulation_config(const v1::Scenario& scenario, int threads = 0);

struct BuildOptions {
  int threads = 0;  // 0: OpenMP's default
  std::string datasets_dir = KESSLER_DATASETS_DIR;
  // False: no checkpoints are taken (a host with nowhere to keep them saves the time).
  bool checkpoints = true;
};

// The run the scenario describes: validates, ingests the population, builds the propagator.
// Returns nullptr with *error set when the scenario cannot run (an empty population after filters too).
std::unique_ptr<Simulation> build_simulation(const v1::Scenario& scenario, const BuildOptions& options,
                                             FieldError* error);

// The same run continued from a checkpoint taken by it.
std::unique_ptr<Simulation> resume_simulation(const v1::Scenario& scenario, const std::string& checkpoint,
                                              const BuildOptions& options, FieldError* error);

}  // namespace kessler
