// kessler-bench conjunctions: propagation (default integrator, full force model) plus conjunction detection
// on the leo-19647 population (the first N objects; beyond 19,647, copies with positions scaled by 1 + 1e-6
// copy); objects below 150 km are removed after each step's detection, as in the simulation. Each step's
// detection runs --repeats times; the median of the repeats' totals is reported (detection time only, x
// threads, per object and step).
#include <omp.h>

#include <time.h>

#include <algorithm>
#include <cstdio>
#include <iostream>

#include "core/conjunctions/detector.hpp"
#include "core/integration/burn_up.hpp"
#include "core/integration/symplectic_propagator.hpp"
#include "core/population/leo19647.hpp"
#include "tests/bench/bench.hpp"

namespace kessler::bench {
namespace {

int run(int argc, char** argv) {
  Args args(argc, argv);
  args.allow_only({"--objects", "--steps", "--threads", "--kappa", "--screen-km", "--dt", "--repeats",
                   "--dataset", "--narrow", "--active-every"});
  const auto objects = static_cast<std::size_t>(args.get_int("--objects", 19647));
  const auto steps = args.get_int("--steps", 100);
  const int threads = static_cast<int>(args.get_int("--threads", 1));
  const int repeats = static_cast<int>(args.get_int("--repeats", 5));
  const double dt = args.get_double("--dt", 10.0);
  const std::string dir = args.get("--dataset", std::string(KESSLER_DATASETS_DIR) + "/leo-19647");
  const std::string narrow = args.get("--narrow", "hermite");
  if (objects < 2 || steps <= 0 || threads <= 0 || repeats <= 0) {
    std::cerr << "kessler-bench conjunctions: --objects >= 2, --steps, --threads, --repeats positive\n";
    return 2;
  }
  if (args.has("--kappa") && args.has("--screen-km")) {
    std::cerr << "kessler-bench conjunctions: give --kappa or --screen-km, not both\n";
    return 2;
  }
  if (narrow != "hermite" && narrow != "linear") {
    std::cerr << "kessler-bench conjunctions: --narrow is 'hermite' or 'linear'\n";
    return 2;
  }
  ConjunctionSettings settings;
  settings.kappa_max = args.get_double("--kappa", 10.0);
  settings.screening_distance_m = args.get_double("--screen-km", 0.0) * 1e3;
  settings.narrow_phase = narrow == "linear" ? NarrowPhase::kLinear : NarrowPhase::kHermite;
  if (auto problem = ConjunctionDetector::validate(settings, dt)) {
    std::cerr << "kessler-bench conjunctions: " << *problem << "\n";
    return 2;
  }

  Population population = leo19647_repeated(dir, objects);
  // Every k-th object active (0: none), to exercise the status rules; the dataset has no status.
  const auto active_every = args.get_int("--active-every", 0);
  if (active_every > 0)
    for (std::size_t i = 0; i < objects; i += static_cast<std::size_t>(active_every))
      population.status[i] = ObjectStatus::kActive;

  omp_set_num_threads(threads);
  SymplecticPropagator propagator(ForceModelSettings{}, leo19647_epoch());
  propagator.set_threads(threads);
  // The simulation's order: propagate, detect on the step's two ends, then remove burn-ups (150 km).
  // Detection runs --repeats times on each step (the first one's events are kept); each repeat's time
  // is summed over the steps and the median of the sums reported. Memory stays O(N) for long runs.
  ConjunctionDetector detector(settings);
  std::vector<double> detect_walls(static_cast<std::size_t>(repeats), 0.0), detect_cpu = detect_walls;
  double grid = 0.0, propagate_s = 0.0;
  std::size_t candidates = 0, collisions = 0, evasions = 0, burn_ups = 0;
  std::vector<Encounter> found, scratch;
  std::vector<char> flags;
  StateArrays start_states;
  for (std::int64_t s = 0; s < steps; ++s) {
    const double t0 = static_cast<double>(s) * dt;
    // The start states are copied in the propagator's own pass, as the simulation does: each thread
    // copies the chunk it propagates, so the detector's passes read them on the core that wrote them.
    const double propagate_start = now_s();
    propagator.step_keeping_start(population, t0, dt, start_states);
    propagate_s += now_s() - propagate_start;
    const StepEnds step{t0, dt, &start_states, &population.state, propagator.last_chunks()};
    for (int rep = 0; rep < repeats; ++rep) {
      scratch.clear();
      const double wall_start = now_s(), cpu_start = process_cpu_s();
      detector.scan(population, step, rep == 0 ? found : scratch);
      detect_walls[static_cast<std::size_t>(rep)] += now_s() - wall_start;
      detect_cpu[static_cast<std::size_t>(rep)] += process_cpu_s() - cpu_start;
      if (rep == 0) {
        candidates += detector.last_candidate_pairs();
        grid += detector.last_grid_s();
      }
    }
    const auto gone = find_burn_ups(population, 150e3, t0 + dt, flags);
    if (!gone.empty()) {
      burn_ups += gone.size();
      population.remove_flagged(flags);
    }
  }
  const std::size_t events = found.size();
  for (int rep = 0; rep < repeats; ++rep)
    std::printf("repeat %d: detection %.4f s, %.1f ns/object-step\n", rep + 1,
                detect_walls[static_cast<std::size_t>(rep)],
                detect_walls[static_cast<std::size_t>(rep)] * threads * 1e9 /
                    (static_cast<double>(objects) * static_cast<double>(steps)));
  for (const Encounter& e : found) {
    collisions += e.kind == EncounterKind::kCollision;
    evasions += e.kind == EncounterKind::kEvasion;
  }
  const double detect = median(detect_walls);
  const double object_steps = static_cast<double>(objects) * static_cast<double>(steps);
  JsonLine line;
  line.add("benchmark", std::string("conjunctions"))
      .add("objects", static_cast<std::int64_t>(objects))
      .add("steps", steps)
      .add("threads", static_cast<std::int64_t>(threads))
      .add("dt_s", dt)
      .add("narrow_phase", narrow)
      .add("kappa_max", settings.kappa_max)
      .add("screening_km", settings.screening_distance_m / 1e3)
      .add("repeats", static_cast<std::int64_t>(repeats))
      .add("wall_s", propagate_s + detect)
      .add("propagate_s", propagate_s)
      .add("detect_s", detect)
      .add("events", static_cast<std::int64_t>(events))
      .add("collisions", static_cast<std::int64_t>(collisions))
      .add("evasions", static_cast<std::int64_t>(evasions))
      .add("burn_ups", static_cast<std::int64_t>(burn_ups))
      .add("candidate_pairs_per_step", static_cast<double>(candidates) / static_cast<double>(steps))
      .add("detect_ns_per_object_step", detect * threads * 1e9 / object_steps)
      .add("detect_ns_per_object_step_min",
           *std::min_element(detect_walls.begin(), detect_walls.end()) * threads * 1e9 / object_steps)
      // CPU time of the process during detection: with 1 thread, immune to time-slicing by other load.
      .add("detect_cpu_ns_per_object_step", median(detect_cpu) * 1e9 / object_steps)
      .add("detect_ns_per_object_step_first_repeat", detect_walls[0] * threads * 1e9 / object_steps)
      .add("grid_ns_per_object_step", grid * threads * 1e9 / object_steps)
      .add("grid_cell_km", detector.grid().cell_size_m() / 1e3)
      .add("grid_column_km", detector.grid().column_width_m() / 1e3)
      .add("grid_rekeyed_fraction",
           static_cast<double>(detector.grid().rekeyed_builds()) /
               static_cast<double>(std::max<std::size_t>(detector.grid().builds(), 1)));
  if (threads >= 2) add_cross_core(line);  // where the host put the cores: 2-thread figures follow it
  line.print();
  return 0;
}

}  // namespace

KESSLER_BENCH("conjunctions",
              "propagation + conjunction detection on leo-19647: --objects N --steps S --threads T "
              "[--kappa K | --screen-km D] [--dt SECONDS] [--repeats R] [--narrow hermite|linear]",
              run);

}  // namespace kessler::bench
