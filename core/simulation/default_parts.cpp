// The project's own parts: ConjunctionDetector and find_burn_ups. Kept apart from the loop so that a
// program that hands in its own parts (tests) does not link the defaults.
#include "core/conjunctions/detector.hpp"
#include "core/integration/burn_up.hpp"
#include "core/simulation/simulation.hpp"

namespace kessler {
namespace {

class DetectorScanner final : public EncounterScanner {
 public:
  explicit DetectorScanner(const ConjunctionSettings& settings) : detector_(settings) {}
  void scan(const Population& population, const StepEnds& step, std::vector<Encounter>& out) override {
    detector_.scan(population, step, out);
  }
  double last_grid_s() const override { return detector_.last_grid_s(); }

 private:
  ConjunctionDetector detector_;
};

}  // namespace

SimulationParts default_parts(const SimulationConfig& config, std::unique_ptr<Propagator> propagator) {
  SimulationParts parts;
  parts.propagator = std::move(propagator);
  if (config.conjunctions_enabled) parts.scanner = std::make_unique<DetectorScanner>(config.conjunctions);
  parts.find_burn_ups = &find_burn_ups;
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
