// kessler-bench run: the whole simulation in-process through the real Simulation (symplectic propagator,
// burn-up, conjunction detection, event assembly) with a counting sink (no I/O unless --events-out).
// The step and integrator default to the scenario defaults (30 s, blanes_moan4); --dt and --integrator
// yoshida4 give the paper's.
//
//   leo-19647: the dataset with J2, C22/S22 and drag under the dataset's density fit, SRP off (the
//              physics of cascade's published benchmark); --objects N takes the first N objects.
//   paper:     the bundled 2022 catalog after the paper's filters (ingest, SGP4 to 2022-01-01), full
//              force model (Kepler, J2, C22/S22, drag on the density table, SRP with shadow).
//   synthetic: the seeded synthetic generator with --objects N (full force model).
//
// Reports wall and process CPU time, core seconds per simulated day (wall x threads / days), cost per
// object-step, the phase timers, peak RSS and memory per object. Checkpoints are off.
#include <omp.h>
#include <sys/resource.h>
#include <time.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <memory>
#include <set>
#include <string>
#include <utility>

#include "core/catalog/bundled_datasets.hpp"
#include "core/catalog/ingest.hpp"
#include "core/catalog/leo19647.hpp"
#include "core/catalog/synthetic.hpp"
#include "core/conjunctions/detector.hpp"
#include "core/integration/symplectic_propagator.hpp"
#include "core/parallel/team_timeline.hpp"
#include "core/simulation/simulation.hpp"
#include "core/simulation/simulation_parts.hpp"
#include "tests/bench/bench.hpp"

namespace kessler::bench {
namespace {

// The default step. The step-independence check decides what may go here (tests/speed, and the one-day
// leo-19647 check of the README's performance section): it fails for a few low-perigee objects with
// drag already between 10 and 5 s, so no larger default is allowed.
const double kDefaultDt_s = SimulationConfig{}.dt_s;

// Resident set size now [bytes], from /proc/self/statm (0 where unavailable).
std::int64_t current_rss_bytes() {
  std::ifstream statm("/proc/self/statm");
  long long pages_total = 0, pages_resident = 0;
  if (!(statm >> pages_total >> pages_resident)) return 0;
  return static_cast<std::int64_t>(pages_resident) * 4096;
}

std::int64_t peak_rss_bytes() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<std::int64_t>(usage.ru_maxrss) * 1024;  // Linux reports kilobytes
}

// The project's detector, and figures of its grid after each scan: the cell edges, and how evenly the
// regions of space share the objects (the slots of the fullest region over the mean, 1 = even). A region's
// thread sorts its slots alone and walks them first, so a full region holds the team up. The figure depends
// only on the population and the team's size, not on timing: a team of 16 on a 2-core machine gives the
// 16-core machine's.
class GridFiguresScanner final : public EncounterScanner {
 public:
  GridFiguresScanner(const ConjunctionSettings& settings, std::size_t team, std::size_t regions)
      : settings_(settings), detector_(settings, GridSettings{regions}), team_(team), regions_(regions) {}
  void scan(const Population& population, const StepEnds& step, std::vector<Encounter>& out) override {
    detector_.scan(population, step, out);
    const BroadPhaseGrid& grid = detector_.grid();
    cell_km_sum_ += grid.cell_size_m() / 1e3;
    column_km_sum_ += grid.column_width_m() / 1e3;
    ++all_scans_;
    // A step in flight is scanned by one thread: its grid has one region.
    if (team_ < 2 || omp_in_parallel() || grid.slot_count() == 0) return;
    std::size_t fullest = 0;
    for (std::size_t t = 0; t < team_; ++t) {
      const auto [first, last] = grid.sorted_slots(t, team_);
      fullest = std::max(fullest, last - first);
    }
    fullest_over_mean_sum_ +=
        static_cast<double>(fullest) * static_cast<double>(team_) / static_cast<double>(grid.slot_count());
    ++scans_;
  }
  double last_grid_s() const override { return detector_.last_grid_s(); }
  // Steps in flight: the others' grids have one region each (a team of one), and their figures are
  // left out.
  std::unique_ptr<EncounterScanner> another() const override {
    return std::make_unique<GridFiguresScanner>(settings_, 1, regions_);
  }
  // The grid's cell edges [km], along y and z and along x (the columns), averaged over the scans.
  double mean_cell_km() const {
    return all_scans_ > 0 ? cell_km_sum_ / static_cast<double>(all_scans_) : 0.0;
  }
  double mean_column_km() const {
    return all_scans_ > 0 ? column_km_sum_ / static_cast<double>(all_scans_) : 0.0;
  }
  // The mean over the scans so far of the fullest region's slots over the mean (0 before any).
  double fullest_region_over_mean() const {
    return scans_ > 0 ? fullest_over_mean_sum_ / static_cast<double>(scans_) : 0.0;
  }

 private:
  ConjunctionSettings settings_;
  ConjunctionDetector detector_;
  std::size_t team_, regions_;
  double fullest_over_mean_sum_ = 0.0, cell_km_sum_ = 0.0, column_km_sum_ = 0.0;
  std::size_t scans_ = 0, all_scans_ = 0;
};

// Counts events; writes encounters as CSV when given a file (for comparisons between runs).
class CountingSink final : public EventSink {
 public:
  explicit CountingSink(std::FILE* events_out) : out_(events_out) {
    if (out_) std::fprintf(out_, "id1,id2,tca_s,miss_m,kind\n");
  }
  void on_encounter(std::uint64_t, const Encounter& e) override {
    ++encounters;
    pairs.emplace(e.id1, e.id2);
    if (out_)
      std::fprintf(out_, "%llu,%llu,%.9f,%.6f,%d\n", static_cast<unsigned long long>(e.id1),
                   static_cast<unsigned long long>(e.id2), e.tca_s, e.miss_distance_m,
                   static_cast<int>(e.kind));
  }
  void on_burn_up(std::uint64_t, const BurnUp&) override { ++burn_ups; }
  void on_progress(std::uint64_t, const Progress&) override { ++progress; }
  void on_checkpoint(std::uint64_t, std::int64_t, const std::string&) override {}
  void on_finished(const RunSummary&) override {}
  void on_failed(const std::string& reason) override {
    std::cerr << "kessler-bench run: failed: " << reason << "\n";
  }

  std::uint64_t encounters = 0, burn_ups = 0, progress = 0;
  std::set<std::pair<ObjectId, ObjectId>> pairs;

 private:
  std::FILE* out_;
};

// The project's parts, each wrapped to add up the process CPU time it takes: the phase timers of the
// summary are wall time, which on a shared machine counts the time other programs hold the core.
class CpuTimedPropagator final : public Propagator {
 public:
  explicit CpuTimedPropagator(std::unique_ptr<Propagator> inner) : inner_(std::move(inner)) {}
  void step(Population& population, double t_start_s, double dt_s) override {
    const double start = process_cpu_s();
    inner_->step(population, t_start_s, dt_s);
    cpu_s += process_cpu_s() - start;
  }
  void step_with(Population& population, double t_start_s, double dt_s, const StepRequest& request) override {
    const double start = process_cpu_s();
    inner_->step_with(population, t_start_s, dt_s, request);
    cpu_s += process_cpu_s() - start;
  }
  double cpu_s = 0.0;

 private:
  std::unique_ptr<Propagator> inner_;
};

// No copies (EncounterScanner::another()): the process's CPU time around scans side by side would
// count each one twice, so with --cpu-times the loop scans one step at a time.
class CpuTimedScanner final : public EncounterScanner {
 public:
  explicit CpuTimedScanner(std::unique_ptr<EncounterScanner> inner) : inner_(std::move(inner)) {}
  void scan(const Population& population, const StepEnds& step, std::vector<Encounter>& out) override {
    const double start = process_cpu_s();
    inner_->scan(population, step, out);
    cpu_s += process_cpu_s() - start;
  }
  double last_grid_s() const override { return inner_->last_grid_s(); }
  double cpu_s = 0.0;

 private:
  std::unique_ptr<EncounterScanner> inner_;
};

Population first_n(Population all, std::size_t n) {
  if (n == 0 || n >= all.size()) return all;
  Population p;
  p.reserve(n);
  for (std::size_t i = 0; i < n; ++i) p.add(all.record(i));
  return p;
}

int run(int argc, char** argv) {
  Args args(argc, argv);
  args.allow_only({"--dataset", "--objects", "--days", "--threads", "--kappa", "--screen-km", "--dt",
                   "--events-out", "--seed", "--no-detection", "--narrow", "--integrator", "--phase-times",
                   "--cpu-times", "--no-cpu-times", "--regions", "--steps-at-once"});
  const std::string dataset = args.get("--dataset", "leo-19647");
  const double days = args.get_double("--days", 1.0);
  const int threads = static_cast<int>(args.get_int("--threads", 1));
  const double dt = args.get_double("--dt", kDefaultDt_s);
  const std::int64_t objects_wanted = args.get_int("--objects", dataset == "synthetic" ? 20000 : 0);
  const std::int64_t regions_wanted = args.get_int("--regions", 0);
  const std::int64_t steps_at_once = args.get_int("--steps-at-once", 0);
  const auto seed = static_cast<std::uint64_t>(args.get_int("--seed", 1));
  const std::string narrow = args.get("--narrow", "hermite");
  const std::string integrator =
      args.get("--integrator", std::string(integrator_name(SimulationConfig{}.integrator)));
  if (dataset != "leo-19647" && dataset != "paper" && dataset != "synthetic") {
    std::cerr << "kessler-bench run: --dataset is leo-19647, paper or synthetic, got '" << dataset << "'\n";
    return 2;
  }
  if (!(days > 0.0) || threads <= 0 || !(dt > 0.0) || objects_wanted < 0) {
    std::cerr << "kessler-bench run: --days and --dt must be positive, --threads >= 1, --objects >= 0\n";
    return 2;
  }
  if (regions_wanted < 0 || regions_wanted > static_cast<std::int64_t>(BroadPhaseGrid::kMaxRegions)) {
    std::cerr << "kessler-bench run: --regions must be 0 (one per thread) to " << BroadPhaseGrid::kMaxRegions
              << ", got " << regions_wanted << "\n";
    return 2;
  }
  const auto regions = static_cast<std::size_t>(regions_wanted);
  if (steps_at_once < 0 || steps_at_once > 1024) {
    std::cerr << "kessler-bench run: --steps-at-once must be 0 (one per thread) to 1024, got "
              << steps_at_once << "\n";
    return 2;
  }
  if (args.has("--kappa") && args.has("--screen-km")) {
    std::cerr << "kessler-bench run: give --kappa or --screen-km, not both\n";
    return 2;
  }
  const std::optional<Integrator> composition = integrator_from_name(integrator);
  if (!composition) {
    std::cerr << "kessler-bench run: --integrator is yoshida4 or blanes_moan4\n";
    return 2;
  }
  if (narrow != "hermite" && narrow != "linear") {
    std::cerr << "kessler-bench run: --narrow is hermite or linear\n";
    return 2;
  }

  SimulationConfig config;
  config.duration_s = days * 86400.0;
  config.dt_s = dt;
  config.integrator = *composition;
  config.threads = threads;
  config.scan_steps_at_once = static_cast<int>(steps_at_once);
  config.seed = seed;
  config.checkpoint_every_steps = 0;
  config.checkpoint_every_wall_s = 0.0;
  config.conjunctions_enabled = !args.has("--no-detection");
  config.conjunctions.kappa_max = args.get_double("--kappa", 10.0);
  config.conjunctions.screening_distance_m = args.get_double("--screen-km", 0.0) * 1e3;
  config.conjunctions.narrow_phase = narrow == "linear" ? NarrowPhase::kLinear : NarrowPhase::kHermite;
  if (config.conjunctions_enabled) {
    if (auto problem = ConjunctionDetector::validate(config.conjunctions, config.dt_s)) {
      std::cerr << "kessler-bench run: " << *problem << "\n";
      return 2;
    }
  }
  if (total_steps_of(config) < 1) {
    std::cerr << "kessler-bench run: --days shorter than one step of --dt\n";
    return 2;
  }

  const std::int64_t rss_before = current_rss_bytes();
  const double load_start = now_s();
  Population population;
  try {
    if (dataset == "leo-19647") {
      config.start_epoch = leo19647_epoch();
      config.force_model.srp = false;
      config.force_model.atmosphere = AtmosphereModel::kExponentialFit;
      population = first_n(load_leo19647(default_datasets_dir() + "/leo-19647"),
                           static_cast<std::size_t>(objects_wanted));
    } else if (dataset == "paper") {
      std::string error;
      auto input = load_bundled_catalog("catalog-2022", default_datasets_dir(), &error);
      if (!input) {
        std::cerr << "kessler-bench run: " << error << "\n";
        return 1;
      }
      IngestResult ingested = ingest_catalog(*input, IngestRules{}, config.start_epoch, seed);
      if (ingested.refused) {
        std::cerr << "kessler-bench run: catalog refused: " << ingested.error << "\n";
        return 1;
      }
      population = first_n(std::move(ingested.population), static_cast<std::size_t>(objects_wanted));
    } else {
      SyntheticOptions options;
      options.objects = static_cast<std::uint64_t>(objects_wanted);
      population = generate_synthetic(options, seed);
    }
    validate_for_propagation(population);
  } catch (const std::exception& e) {
    std::cerr << "kessler-bench run: " << dataset << ": " << e.what() << "\n";
    return 1;
  }
  const double load_s = now_s() - load_start;
  if (population.size() == 0) {
    std::cerr << "kessler-bench run: " << dataset << ": no objects to simulate (--objects)\n";
    return 2;
  }
  const std::size_t objects = population.size();

  std::FILE* events_out = nullptr;
  if (args.has("--events-out")) {
    events_out = std::fopen(args.get("--events-out", "").c_str(), "w");
    if (!events_out) {
      std::cerr << "kessler-bench run: cannot write " << args.get("--events-out", "") << "\n";
      return 1;
    }
  }

  omp_set_num_threads(threads);
  // Where each thread of the step's parallel regions spends its time (team_timeline.hpp), handed to the
  // propagator and, through the parts, to the loop's scans.
  const bool phase_times = args.has("--phase-times");
  PhaseTimelines timelines;
  PhaseTimelines* const timed = phase_times ? &timelines : nullptr;
  auto propagator = std::make_unique<SymplecticPropagator>(
      config.force_model, config.start_epoch, config.integrator, timed ? &timed->propagator : nullptr);
  propagator->set_threads(threads);
  RunSummary summary;
  CountingSink sink(events_out);
  double wall = 0.0, cpu = 0.0, integrator_cpu = 0.0, detection_cpu = 0.0, fullest_region = 0.0,
         cell_km = 0.0, column_km = 0.0;
  SimulationParts parts = default_parts(config, std::move(propagator));
  GridFiguresScanner* grid_figures = nullptr;
  if (parts.scanner) {
    auto scanner =
        std::make_unique<GridFiguresScanner>(config.conjunctions, static_cast<std::size_t>(threads), regions);
    grid_figures = scanner.get();
    parts.scanner = std::move(scanner);
  }
  // The per-part CPU clocks read the whole process's CPU time (a system call that visits every thread,
  // ~2 us here) four times a step, on the master thread while the others wait: 1-2 % of a leo-19647
  // run's wall time on 1 or 2 threads. So they are asked for (--cpu-times), not on by default;
  // --no-cpu-times is still accepted. The run's total CPU time is read once at each end either way.
  const bool cpu_times = args.has("--cpu-times") && !args.has("--no-cpu-times");
  CpuTimedPropagator* propagator_cpu = nullptr;
  if (cpu_times) {
    auto timed_propagator = std::make_unique<CpuTimedPropagator>(std::move(parts.propagator));
    propagator_cpu = timed_propagator.get();
    parts.propagator = std::move(timed_propagator);
  }
  CpuTimedScanner* scanner_cpu = nullptr;
  if (cpu_times && parts.scanner) {
    auto timed_scanner = std::make_unique<CpuTimedScanner>(std::move(parts.scanner));
    scanner_cpu = timed_scanner.get();
    parts.scanner = std::move(timed_scanner);
  }
  parts.timelines = timed;
  try {
    Simulation simulation(config, std::move(population), std::move(parts));
    RunControl control;
    const double wall_start = now_s(), cpu_start = process_cpu_s();
    summary = simulation.run(sink, control);
    wall = now_s() - wall_start;
    cpu = process_cpu_s() - cpu_start;
    // Read while the simulation (which owns the parts) lives.
    integrator_cpu = propagator_cpu ? propagator_cpu->cpu_s : 0.0;
    detection_cpu = scanner_cpu ? scanner_cpu->cpu_s : 0.0;
    if (grid_figures) {
      fullest_region = grid_figures->fullest_region_over_mean();
      cell_km = grid_figures->mean_cell_km();
      column_km = grid_figures->mean_column_km();
    }
  } catch (const std::exception& e) {
    std::cerr << "kessler-bench run: " << e.what() << "\n";
    if (events_out) std::fclose(events_out);
    return 1;
  }
  if (events_out) std::fclose(events_out);

  const std::int64_t peak = peak_rss_bytes();
  const double sim_days = summary.sim_time_s / 86400.0;
  // Object-steps: objects alive at the start of each step; burn-ups change it by a few per mille.
  const double object_steps = static_cast<double>(objects) * static_cast<double>(summary.steps);
  const auto& t = summary.timers;
  std::printf("%s: %zu objects, %lld steps of %g s, %d thread(s), load %.1f s\n", dataset.c_str(), objects,
              static_cast<long long>(summary.steps), dt, threads, load_s);
  std::printf(
      "phases [s]: integrator %.2f, burn-up %.2f, grid %.2f, detection %.2f, output %.2f, total %.2f\n",
      t.integrator_s, t.burn_up_s, t.grid_s, t.detection_s, t.output_s, t.total_s);
  double loadavg[1] = {0.0};
  if (getloadavg(loadavg, 1) < 1) loadavg[0] = NAN;
  JsonLine line;
  line.add("benchmark", std::string("run"))
      .add("dataset", dataset)
      .add("objects", static_cast<std::int64_t>(objects))
      .add("days", sim_days)
      .add("dt_s", dt)
      .add("integrator", integrator)
      .add("steps", summary.steps)
      .add("threads", static_cast<std::int64_t>(threads))
      .add("kappa_max", config.conjunctions.screening_distance_m > 0 ? 0.0 : config.conjunctions.kappa_max)
      .add("screening_km", config.conjunctions.screening_distance_m / 1e3)
      .add("detection", std::string(config.conjunctions_enabled ? narrow : "off"))
      .add("wall_s", wall)
      .add("cpu_s", cpu)
      .add("core_s_per_sim_day", wall * threads / sim_days)
      .add("cpu_s_per_sim_day", cpu / sim_days)
      .add("ns_per_object_step", wall * threads * 1e9 / object_steps)
      .add("cpu_ns_per_object_step", cpu * 1e9 / object_steps)
      .add("events", static_cast<std::int64_t>(summary.events))
      .add("encounters", static_cast<std::int64_t>(sink.encounters))
      .add("conjunctions", static_cast<std::int64_t>(summary.conjunctions))
      .add("collisions", static_cast<std::int64_t>(summary.collisions))
      .add("evasions", static_cast<std::int64_t>(summary.evasions))
      .add("burn_ups", static_cast<std::int64_t>(summary.burn_ups))
      .add("distinct_pairs", static_cast<std::int64_t>(sink.pairs.size()))
      .add("objects_final", static_cast<std::int64_t>(summary.objects_final))
      .add("integrator_s", t.integrator_s)
      .add("burn_up_s", t.burn_up_s)
      .add("grid_s", t.grid_s)
      .add("detection_s", t.detection_s)
      .add("output_s", t.output_s)
      .add("checkpoint_s", t.checkpoint_s)
      .add("total_s", t.total_s)
      .add("peak_rss_bytes", peak)
      .add("bytes_per_object", static_cast<double>(peak - rss_before) / static_cast<double>(objects))
      .add("load_average", loadavg[0])
      .add("events_digest", summary.events_digest);
  if (cpu_times) {
    line.add("integrator_cpu_s", integrator_cpu)
        .add("detection_cpu_s", detection_cpu)
        .add("other_cpu_s", cpu - integrator_cpu - detection_cpu);
  }
  if (phase_times) {
    // Per segment: the mean over the threads and the largest, seconds summed over the run.
    for (auto [prefix, timeline] :
         {std::pair{"prop", &timelines.propagator}, std::pair{"det", &timelines.detector},
          std::pair{"flight", &timelines.flight}}) {
      for (std::size_t s = 0; s < timeline->segments().size(); ++s) {
        const auto [mean, most] = timeline->mean_and_max(static_cast<int>(s));
        const std::string key = std::string("t_") + prefix + "_" + timeline->segments()[s];
        line.add(key + "_mean_s", mean).add(key + "_max_s", most);
        if (threads <= 4) {  // each thread's, where a team is small enough to read them
          std::string each;
          for (const double seconds : timeline->per_thread(static_cast<int>(s)))
            each += (each.empty() ? "" : " ") + std::to_string(seconds);
          line.add(key + "_each_s", each);
        }
      }
    }
  }
  if (grid_figures) line.add("grid_cell_km_mean", cell_km).add("grid_column_km_mean", column_km);
  if (threads >= 2) line.add("fullest_region_over_mean", fullest_region);
  if (threads >= 2) add_cross_core(line);  // where the host put the cores: 2-thread figures follow it
  line.print();
  return 0;
}

}  // namespace

KESSLER_BENCH("run",
              "the whole simulation: --dataset leo-19647|paper|synthetic [--objects N] --days D --threads T "
              "[--kappa K | --screen-km S] [--dt SECONDS] [--events-out FILE] [--no-detection] "
              "[--narrow hermite|linear] [--seed S] [--integrator yoshida4|blanes_moan4] [--phase-times] "
              "[--cpu-times] [--regions R]",
              run);

}  // namespace kessler::bench
