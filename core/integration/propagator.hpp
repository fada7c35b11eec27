// The interface every propagator (numerical Yoshida, SGP4) offers the simulation loop, and the view of
// one step that conjunction detection reads.
#pragma once

#include "core/population/population.hpp"

namespace kessler {

// Positions and velocities of every object at both ends of one step, index-aligned with the population
// (the objects alive for the whole step; burn-ups are removed after detection). Detection interpolates
// between the two ends; times are seconds since the scenario epoch.
struct StepEnds {
  double t_start_s = 0.0;
  double dt_s = 0.0;
  const StateArrays* start = nullptr;
  const StateArrays* end = nullptr;
};

class Propagator {
 public:
  virtual ~Propagator() = default;
  // Advances population.state from t_start_s to t_start_s + dt_s (seconds since the scenario epoch),
  // in parallel over objects. Each object's new state depends on that object alone, so results are
  // bitwise identical for any thread count.
  virtual void step(Population& population, double t_start_s, double dt_s) = 0;
  // The same, and the states at t_start_s copied into start_out (the start of the step's StepEnds).
  // Propagators that read every state anyway override this to copy in the same parallel pass: a
  // separate copy is a serial pass over 48 bytes per object per step.
  virtual void step_keeping_start(Population& population, double t_start_s, double dt_s,
                                  StateArrays& start_out) {
    start_out = population.state;
    step(population, t_start_s, dt_s);
  }
};

}  // namespace kessler
