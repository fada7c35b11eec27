// The project's own parts, and the contract constructors that use them. Kept apart from the loop so
// that a program handing in its own parts (the tests) does not link the defaults.
#include "core/simulation/simulation.hpp"

namespace kessler {

SimulationParts default_parts(const SimulationConfig& config, std::unique_ptr<Propagator> propagator) {
  SimulationParts parts;
  parts.propagator = std::move(propagator);
  if (config.conjunctions_enabled) {
    ConjunctionSettings conjunctions = config.conjunctions;
    conjunctions.seed = config.seed;  // the evasion draws'
    parts.scanner = make_detector_scanner(conjunctions);
  }
  return parts;
}

Simulation::Simulation(const SimulationConfig& config, Population population,
                       std::unique_ptr<Propagator> propagator)
    : Simulation(config, std::move(population), default_parts(config, std::move(propagator))) {}

std::unique_ptr<Simulation> Simulation::resume(const SimulationConfig& config, const std::string& checkpoint,
                                               std::unique_ptr<Propagator> propagator) {
  return resume(config, checkpoint, default_parts(config, std::move(propagator)));
}

}  // namespace kessler
