// One run: the paper's main loop (integrate, burn-up, conjunction detection, events, progress,
// checkpoints) over a population, with pause, cancel and resume.
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <string>

#include "core/conjunctions/encounter.hpp"
#include "core/integration/composition.hpp"
#include "core/integration/propagator.hpp"
#include "core/physics/force_model_settings.hpp"
#include "core/population/population.hpp"
#include "core/simulation/events.hpp"
#include "core/simulation/simulation_parts.hpp"
#include "core/time/epoch.hpp"

namespace kessler {

// The core's plain view of a scenario (core/scenario/ maps the proto onto it).
struct SimulationConfig {
  UtcEpoch start_epoch = UtcEpoch::from_calendar(2022, 1, 1, 0, 0, 0.0);
  double duration_s = 86400.0;
  double dt_s = 30.0;
  // The numerical propagator's composition (composition.hpp).
  Integrator integrator = Integrator::kBlanesMoan4;
  ForceModelSettings force_model;
  bool conjunctions_enabled = true;
  ConjunctionSettings conjunctions;
  double burn_up_altitude_m = 150e3;
  std::int64_t checkpoint_every_steps = 0;  // 0: off
  double checkpoint_every_wall_s = 0.0;     // 0: off
  std::int64_t progress_every_steps = 0;    // 0: about 200 per run
  // A population snapshot (snapshots.hpp) at the start, every this many steps and at the last step;
  // 0: none. Never changes an event, a digest or a checkpoint's key.
  std::int64_t snapshot_every_steps = 0;
  std::uint64_t seed = 1;
  int threads = 0;  // 0: OpenMP's default
  // Steps whose conjunction scans run side by side, each on one thread (steps_in_flight.hpp); 0: one
  // per thread where their memory fits steps_in_flight_for's budget, else 1; 1: one step at a time on
  // the whole team. Never changes a result.
  int scan_steps_at_once = 0;
  // Breakups (breakups.hpp); off by default, and then nothing of them runs.
  BreakupSettings breakups;
  // Launches and lifecycles (traffic.hpp); off by default, and then nothing of them runs.
  TrafficSettings traffic;
};

// Steps in a run: whole steps of dt_s that fit in duration_s (a last partial step is not taken).
std::int64_t total_steps_of(const SimulationConfig& config);

// Flags a host sets from another thread; the loop reads them at each step boundary between batches of
// steps in flight (every step on one thread; every T steps on T threads: steps_in_flight.hpp).
struct RunControl {
  std::atomic<bool> cancel{false};
  std::atomic<bool> pause{false};
  // Write a checkpoint at the end of the current batch (e.g. on SIGTERM), then clear the flag.
  std::atomic<bool> checkpoint_now{false};
  // Stop after writing the next checkpoint (graceful shutdown: the run stays resumable).
  std::atomic<bool> stop_after_checkpoint{false};
};

class Simulation {
 public:
  // A fresh run of `population` moved by `propagator`.
  Simulation(const SimulationConfig& config, Population population, std::unique_ptr<Propagator> propagator);
  // A fresh run from explicit parts (tests, tools). The contract constructor is this with default_parts.
  Simulation(const SimulationConfig& config, Population population, SimulationParts parts);
  // A run continued from checkpoint bytes (as handed to EventSink::on_checkpoint). The propagator
  // must be built from the same scenario. Throws std::runtime_error on a corrupt checkpoint.
  static std::unique_ptr<Simulation> resume(const SimulationConfig& config, const std::string& checkpoint,
                                            std::unique_ptr<Propagator> propagator);
  static std::unique_ptr<Simulation> resume(const SimulationConfig& config, const std::string& checkpoint,
                                            SimulationParts parts);
  ~Simulation();

  // Runs to the end (or until cancelled), handing every event to `sink`. Returns the summary, which
  // was also handed to sink.on_finished. Failures are reported with sink.on_failed and rethrown.
  RunSummary run(EventSink& sink, RunControl& control);

  const Population& population() const;
  std::int64_t step() const;
  std::int64_t total_steps() const;
  // The closest encounter of every pair seen so far, in canonical order (time, then ids).
  std::vector<Encounter> closest_encounters() const;
  // The checkpoint of the current state (what on_checkpoint receives), e.g. for a host's own triggers
  // between runs.
  std::string checkpoint() const;

 private:
  struct State;
  struct RunLoop;  // the loop of one call of run()
  std::unique_ptr<State> state_;
};

}  // namespace kessler
