// What a Simulation is assembled from: the propagator, the conjunction scan and the burn-up rule. The
// contract constructor (config, population, propagator) takes the project's own detector and burn-up
// rule; tests and tools may hand in others through SimulationParts.
#pragma once

#include <functional>
#include <memory>
#include <vector>

#include "core/conjunctions/encounter.hpp"
#include "core/integration/burn_up.hpp"
#include "core/integration/propagator.hpp"

namespace kessler {

struct PhaseTimelines;
struct SimulationConfig;

// One step's conjunction scan, as ConjunctionDetector::scan: every encounter of the step appended to
// `out` in canonical order, bitwise identical for any thread count.
class EncounterScanner {
 public:
  virtual ~EncounterScanner() = default;
  virtual void scan(const Population& population, const StepEnds& step, std::vector<Encounter>& out) = 0;
  // Seconds of the last scan spent in the broad phase (grid), for the phase timers; 0 if unknown.
  virtual double last_grid_s() const { return 0.0; }
  // A scanner with the same settings and none of this one's scratch, to scan another step at the same
  // time (steps_in_flight.hpp); null where that is not offered (then steps are scanned one at a time).
  virtual std::unique_ptr<EncounterScanner> another() const { return nullptr; }
};

// The objects below min_altitude_m and their removal flags, sized to the population by the finder (the
// signature of find_burn_ups).
using BurnUpFinder = std::function<std::vector<BurnUp>(const Population&, double min_altitude_m,
                                                       double time_s, std::vector<char>& flags)>;

struct SimulationParts {
  std::unique_ptr<Propagator> propagator;
  std::unique_ptr<EncounterScanner> scanner;  // null: no conjunction tracking
  // Burn-up. The project's rule (burns_up) is applied by the propagator in its own pass over the states
  // (StepRequest); a finder, where given, decides instead, after the step (tests hand in a brute-force
  // one). burn_up false: no burn-up.
  bool burn_up = true;
  BurnUpFinder find_burn_ups;
  // Where the loop's steps in flight and step scans time their threads (team_timeline.hpp); null: untimed.
  // The propagator takes its own at construction (SymplecticPropagator).
  PhaseTimelines* timelines = nullptr;
};

// ConjunctionDetector behind the scanner interface.
std::unique_ptr<EncounterScanner> make_detector_scanner(const ConjunctionSettings& settings);

// The project's parts for `config`: `propagator` (which applies the burn-up rule) and ConjunctionDetector
// (when config.conjunctions_enabled).
SimulationParts default_parts(const SimulationConfig& config, std::unique_ptr<Propagator> propagator);

}  // namespace kessler
