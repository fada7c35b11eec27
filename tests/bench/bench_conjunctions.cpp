// kessler-bench conjunctions: propagation (Yoshida, full force model) plus conjunction detection on the
// leo-19647 population (the first N objects; beyond 19,647 copies with positions scaled by
// 1 + 1e-6 copy), objects below 150 km removed after each step's detection as in the simulation. The states
// of every step are propagated once and kept; detection then runs over them
// --repeats times and the median is reported (detection time only, x threads, per object and step).
#include <omp.h>

#include <algorithm>
#include <cstdio>
#include <iostream>

#include "core/conjunctions/detector.hpp"
#include "core/integration/burn_up.hpp"
#include "core/integration/yoshida_propagator.hpp"
#include "core/population/leo19647.hpp"
#include "tests/bench/bench.hpp"

namespace kessler::bench {
namespace {

Population first_objects(const std::string& dir, std::size_t objects) {
  const Population base = load_leo19647(dir);
  Population p;
  p.reserve(objects);
  for (std::size_t i = 0; i < objects; ++i) {
    ObjectRecord r = base.record(i % base.size());
    r.id = i + 1;
    r.position_m *= 1.0 + 1.0e-6 * static_cast<double>(i / base.size());
    p.add(r);
  }
  return p;
}

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

  Population population = first_objects(dir, objects);
  // Every k-th object active (0: none), to exercise the status rules; the dataset has no status.
  const auto active_every = args.get_int("--active-every", 0);
  if (active_every > 0)
    for (std::size_t i = 0; i < objects; i += static_cast<std::size_t>(active_every))
      population.status[i] = ObjectStatus::kActive;

  omp_set_num_threads(threads);
  YoshidaPropagator propagator(ForceModelSettings{}, leo19647_epoch());
  propagator.set_threads(threads);
  // The simulation's order: propagate, detect on the step's two ends, then remove burn-ups (150 km).
  // Snapshots are kept per step; a burn-up starts a new population version and start snapshot.
  struct StepRecord {
    std::size_t start, end, population;
  };
  std::vector<StateArrays> snaps;
  std::vector<Population> populations;
  std::vector<StepRecord> records;
  std::size_t burn_ups = 0;
  snaps.reserve(static_cast<std::size_t>(steps) + 8);
  snaps.push_back(population.state);
  populations.push_back(population);
  const double propagate_start = now_s();
  std::vector<char> flags;
  for (std::int64_t s = 0; s < steps; ++s) {
    propagator.step(population, static_cast<double>(s) * dt, dt);
    snaps.push_back(population.state);
    records.push_back(StepRecord{snaps.size() - 2, snaps.size() - 1, populations.size() - 1});
    const auto gone = find_burn_ups(population, 150e3, static_cast<double>(s + 1) * dt, flags);
    if (!gone.empty()) {
      burn_ups += gone.size();
      population.remove_flagged(flags);
      populations.push_back(population);
      snaps.push_back(population.state);
    }
  }
  const double propagate_s = now_s() - propagate_start;

  ConjunctionDetector detector(settings);
  std::vector<double> detect_walls, grid_walls;
  std::size_t events = 0, candidates = 0, collisions = 0, evasions = 0;
  std::vector<Encounter> found;
  for (int rep = 0; rep < repeats; ++rep) {
    found.clear();
    candidates = 0;
    double grid = 0.0;
    const double start = now_s();
    for (std::int64_t s = 0; s < steps; ++s) {
      const StepRecord& r = records[static_cast<std::size_t>(s)];
      StepEnds step{static_cast<double>(s) * dt, dt, &snaps[r.start], &snaps[r.end]};
      detector.scan(populations[r.population], step, found);
      candidates += detector.last_candidate_pairs();
      grid += detector.last_grid_s();
    }
    detect_walls.push_back(now_s() - start);
    grid_walls.push_back(grid);
    events = found.size();
    std::printf(
        "repeat %d: detection %.4f s (grid and pairs %.4f s), %.1f ns/object-step, %zu events\n", rep + 1,
        detect_walls.back(), grid,
        detect_walls.back() * threads * 1e9 / (static_cast<double>(objects) * static_cast<double>(steps)),
        events);
  }
  for (const Encounter& e : found) {
    collisions += e.kind == EncounterKind::kCollision;
    evasions += e.kind == EncounterKind::kEvasion;
  }
  const double detect = median(detect_walls);
  const double object_steps = static_cast<double>(objects) * static_cast<double>(steps);
  JsonLine()
      .add("benchmark", std::string("conjunctions"))
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
      .add("grid_ns_per_object_step", median(grid_walls) * threads * 1e9 / object_steps)
      .print();
  return 0;
}

}  // namespace

KESSLER_BENCH("conjunctions",
              "Yoshida propagation + conjunction detection on leo-19647: --objects N --steps S --threads T "
              "[--kappa K | --screen-km D] [--dt SECONDS] [--repeats R] [--narrow hermite|linear]",
              run);

}  // namespace kessler::bench
