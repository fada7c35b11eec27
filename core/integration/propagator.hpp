// The interface every propagator (numerical Yoshida, SGP4) offers the simulation loop, and the view of
// one step that conjunction detection reads.
#pragma once

#include <vector>

#include "core/parallel/thread_chunks.hpp"
#include "core/population/population.hpp"

namespace kessler {

class TeamTimeline;

// Positions and velocities of every object at both ends of one step, index-aligned with the population
// (the objects alive for the whole step; burn-ups are removed after detection). Detection interpolates
// between the two ends; times are seconds since the scenario epoch.
struct StepEnds {
  double t_start_s = 0.0;
  double dt_s = 0.0;
  const StateArrays* start = nullptr;
  const StateArrays* end = nullptr;
  // How the propagator shared the objects out between its threads (null: in equal chunks): passes over
  // the end states that split the same way read what their own core wrote.
  const ChunkLayout* chunks = nullptr;
  // Where the step's scan times its threads' phases (team_timeline.hpp, DetectorSegment); null: untimed.
  TeamTimeline* timeline = nullptr;
};

// What the loop asks of a step besides the new states.
struct StepRequest {
  // The states at t_start_s are copied here (the start of the step's StepEnds), when not null.
  StateArrays* start_out = nullptr;
  // Burn-up: when not null, resized to the population and set per object to burns_up(its end position,
  // burn_up_radius2) (burn_up.hpp).
  std::vector<char>* burn_up_flags = nullptr;
  double burn_up_radius2 = 0.0;
  // The states at t_start_s + dt_s are copied here (the end of the step's StepEnds), when not null.
  StateArrays* end_out = nullptr;
};

class Propagator {
 public:
  virtual ~Propagator() = default;
  // Advances population.state from t_start_s to t_start_s + dt_s (seconds since the scenario epoch),
  // in parallel over objects. Each object's new state depends on that object alone, so results are
  // bitwise identical for any thread count.
  virtual void step(Population& population, double t_start_s, double dt_s) = 0;
  // The same, and what `request` asks for. This default copies before the step and flags after it, each
  // in a pass of its own; propagators that read and write every state anyway override it to do both in
  // their own parallel pass.
  virtual void step_with(Population& population, double t_start_s, double dt_s, const StepRequest& request);
  // step_with for the start states alone.
  void step_keeping_start(Population& population, double t_start_s, double dt_s, StateArrays& start_out) {
    step_with(population, t_start_s, dt_s, StepRequest{&start_out});
  }
  // The chunks the last step shared out between threads, where they are not equal ones (else null).
  virtual const ChunkLayout* last_chunks() const { return nullptr; }
  // Whether step() takes objects it was not built with (a breakup's fragments): a force model does,
  // SGP4 (one element set per catalog object) does not.
  virtual bool takes_new_objects() const { return true; }
};

}  // namespace kessler
