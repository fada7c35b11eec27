// kessler-bench conjunctions: propagation (default integrator, full force model) plus conjunction detection
// on the leo-19647 population (the first N objects; beyond 19,647, copies with positions scaled by 1 + 1e-6
// copy); objects below 150 km are removed after each step's detection, as in the simulation. Steps are
// scanned as the simulation scans them: one per thread, side by side (core/simulation/steps_in_flight.hpp;
// --steps-at-once 1: one at a time on the whole team). Each batch's detection runs --repeats times; the
// median of the repeats' totals is reported (detection time only, x threads, per object and step).
#include <omp.h>

#include <time.h>

#include <algorithm>
#include <cstdio>
#include <iostream>

#include "core/catalog/leo19647.hpp"
#include "core/conjunctions/detector.hpp"
#include "core/integration/burn_up.hpp"
#include "core/integration/symplectic_propagator.hpp"
#include "core/simulation/steps_in_flight.hpp"
#include "tests/bench/bench.hpp"

namespace kessler::bench {
namespace {

// The detector, adding up its candidate pairs and broad-phase seconds while `counting`.
class CountingScanner final : public EncounterScanner {
 public:
  explicit CountingScanner(const ConjunctionSettings& settings) : settings_(settings), detector_(settings) {}
  void scan(const Population& population, const StepEnds& step, std::vector<Encounter>& out) override {
    detector_.scan(population, step, out);
    if (!counting) return;
    candidates += detector_.last_candidate_pairs();
    grid_s += detector_.last_grid_s();
  }
  double last_grid_s() const override { return detector_.last_grid_s(); }
  std::unique_ptr<EncounterScanner> another() const override {
    return std::make_unique<CountingScanner>(settings_);
  }
  const ConjunctionDetector& detector() const { return detector_; }
  bool counting = true;
  std::size_t candidates = 0;
  double grid_s = 0.0;

 private:
  ConjunctionSettings settings_;
  ConjunctionDetector detector_;
};

int run(int argc, char** argv) {
  Args args(argc, argv);
  args.allow_only({"--objects", "--steps", "--threads", "--kappa", "--screen-km", "--dt", "--repeats",
                   "--dataset", "--narrow", "--active-every", "--steps-at-once"});
  const auto objects = static_cast<std::size_t>(args.get_int("--objects", 19647));
  const auto steps = args.get_int("--steps", 100);
  const int threads = static_cast<int>(args.get_int("--threads", 1));
  const int repeats = static_cast<int>(args.get_int("--repeats", 5));
  const double dt = args.get_double("--dt", 10.0);
  const std::string dir = args.get("--dataset", std::string(KESSLER_DATASETS_DIR) + "/leo-19647");
  const std::string narrow = args.get("--narrow", "hermite");
  const auto at_once_wanted = args.get_int("--steps-at-once", 0);
  if (objects < 2 || steps <= 0 || threads <= 0 || repeats <= 0 || at_once_wanted < 0 ||
      at_once_wanted > 1024) {
    std::cerr << "kessler-bench conjunctions: --objects >= 2, --steps, --threads, --repeats positive, "
                 "--steps-at-once 0 (one per thread) to 1024\n";
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
  // The simulation's order: propagate a batch of steps, scan them, then remove burn-ups (150 km; a batch
  // ends at a step where objects burn up). Detection runs --repeats times on each batch (the first
  // one's events are kept); each repeat's time is summed over the batches and the median of the sums
  // reported. Memory stays O(N) for long runs.
  CountingScanner first(settings);
  StepsInFlight flight(first, static_cast<std::size_t>(at_once_wanted), population.size(),
                       static_cast<std::size_t>(threads));
  // The scanners are `first` and its copies (CountingScanner::another()).
  std::vector<CountingScanner*> counting;
  for (EncounterScanner* scanner : flight.scanners())
    counting.push_back(static_cast<CountingScanner*>(scanner));
  const std::size_t at_once = flight.capacity();
  std::vector<double> detect_walls(static_cast<std::size_t>(repeats), 0.0), detect_cpu = detect_walls;
  double propagate_s = 0.0;
  std::size_t collisions = 0, evasions = 0, burn_ups = 0;
  std::vector<Encounter> found;
  std::vector<std::vector<Encounter>> batch_found, scratch;
  std::vector<char> flags;
  const StepRequest burn_up_request{nullptr, &flags, burn_up_radius2(150e3)};
  for (std::int64_t s = 0; s < steps;) {
    std::vector<BurnUp> gone;
    while (!flight.full() && s + static_cast<std::int64_t>(flight.size()) < steps && gone.empty()) {
      const double t0 = static_cast<double>(s + static_cast<std::int64_t>(flight.size())) * dt;
      const double propagate_start = now_s();
      const bool last =
          flight.size() + 1 == flight.capacity() || s + static_cast<std::int64_t>(flight.size()) + 1 == steps;
      propagator.step_with(population, t0, dt, flight.request_for_next(burn_up_request, last));
      flight.push(t0, dt, propagator.last_chunks());
      propagate_s += now_s() - propagate_start;
      gone = flagged_burn_ups(population, t0 + dt, flags);
    }
    const std::size_t batch = flight.size();
    for (int rep = 0; rep < repeats; ++rep) {
      for (CountingScanner* c : counting) c->counting = rep == 0;
      std::vector<std::vector<Encounter>>& out = rep == 0 ? batch_found : scratch;
      for (std::vector<Encounter>& o : out) o.clear();
      const double wall_start = now_s(), cpu_start = process_cpu_s();
      flight.scan(population, out);
      detect_walls[static_cast<std::size_t>(rep)] += now_s() - wall_start;
      detect_cpu[static_cast<std::size_t>(rep)] += process_cpu_s() - cpu_start;
    }
    for (std::size_t j = 0; j < batch; ++j)
      found.insert(found.end(), batch_found[j].begin(), batch_found[j].end());
    if (!gone.empty()) {
      burn_ups += gone.size();
      population.remove_flagged(flags);
    }
    flight.restart();
    s += static_cast<std::int64_t>(batch);
  }
  std::size_t candidates = 0;
  double grid = 0.0;
  for (const CountingScanner* c : counting) {
    candidates += c->candidates;
    grid += c->grid_s;
  }
  const ConjunctionDetector& detector = counting[0]->detector();
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
      .add("steps_at_once", static_cast<std::int64_t>(at_once))
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
      // Steps in flight: each scan's seconds are one thread's; one at a time: the team's wall time.
      .add("grid_ns_per_object_step", grid * (at_once > 1 ? 1.0 : threads) * 1e9 / object_steps)
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
