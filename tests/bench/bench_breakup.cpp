// kessler-bench breakup: NASA Standard Breakup Model generation speed for the catastrophic reference
// collision (560 kg + 950 kg spacecraft at 11.7 km/s) down to --lc-min (default 1 cm: 63,713
// fragments). Each repeat generates the whole cloud (event id = repeat); the figure is the median.
//   --lc-min M (default 0.01)  --threads T (default 1)  --repeats R (default 3)
//
// Then two runs of leo-19647 (its physics as in `kessler-bench run`: J2, C22/S22, drag on the dataset's
// density fit, SRP off; kappa 10 conjunction tracking, 30 s, one thread) with a breakup scheduled
// through the core (SimulationConfig::breakups), every step timed from the progress events:
//   insert (--skip-insert): a catastrophic collision of two catalog objects with masses set so that
//     N(>= 1 cm) is ~100,000, at the end of step --insert-step (default 30); insert_s is that step's wall
//     time less the median step before it, insert_steps the same over the median step after it (the
//     grown population, --insert-after steps, default 5). This run propagates without conjunction
//     detection unless --insert-detection; with it (--insert-after default 25) it also prints each
//     step's wall time after the breakup and the run's peak RSS. For separation_s (600 s, 20 steps) the
//     cloud's pairs are dropped before the narrow phase, but its boxes still overlap in the grid.
//   growth (--skip-growth): Iridium 33 / Cosmos 2251 (560 kg + 950 kg at 11.7 km/s, Lc >= 10 cm) at the
//     end of step --growth-steps (default 300), then as many steps again: ns per object-step before and
//     after (the breakup step itself apart), and the encounters of each window by kind of pair.
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>
#include <new>
#include <numeric>
#include <string>
#include <vector>

#include "core/breakup/fragment_cloud.hpp"
#include "core/catalog/bundled_datasets.hpp"
#include "core/catalog/leo19647.hpp"
#include "core/integration/symplectic_propagator.hpp"
#include "core/simulation/breakups.hpp"
#include "core/simulation/simulation.hpp"
#include "core/simulation/simulation_parts.hpp"
#include "tests/bench/bench.hpp"

namespace kessler::bench {
namespace {

// The parents in leo-19647: two of its largest objects near Iridium 33's altitude (ids 5553, 751 km,
// r 2.8 m; 4855, 802 km, r 2.66 m). A scheduled collision takes each parent's state where it is: each
// parent's fragments start at its own position, so the cloud is two clumps. Their sizes (2 r) set
// Lc_max, not the count.
constexpr ObjectId kParentA = 5553, kParentB = 4855;

// Times every step from the progress events (one per step), and counts encounters by kind of pair.
class StepTimingSink final : public EventSink {
 public:
  explicit StepTimingSink(double breakup_time_s) : breakup_time_s_(breakup_time_s) {}
  void start() {
    last_ = now_s();
    last_cpu_ = process_cpu_s();
  }
  void on_encounter(std::uint64_t, const Encounter& e) override {
    const bool after = e.tca_s > breakup_time_s_;
    const int fragments = (e.id1 >= kFirstFragmentId ? 1 : 0) + (e.id2 >= kFirstFragmentId ? 1 : 0);
    ++(after ? after_by_fragments : before_by_fragments)[fragments];
  }
  void on_burn_up(std::uint64_t, const BurnUp&) override {}
  void on_progress(std::uint64_t, const Progress& p) override {
    const double t = now_s(), cpu = process_cpu_s();
    step_s.push_back(t - last_);
    step_cpu_s.push_back(cpu - last_cpu_);
    last_cpu_ = cpu;
    objects_at_start.push_back(alive_);
    alive_ = p.objects_alive;
    last_ = t;
  }
  void on_breakup(std::uint64_t, const BreakupReport& b) override { fragments += b.fragment_count; }
  void on_checkpoint(std::uint64_t, std::int64_t, const std::string&) override {}
  void on_finished(const RunSummary&) override {}
  void on_failed(const std::string& reason) override {
    std::fprintf(stderr, "kessler-bench breakup: run failed: %s\n", reason.c_str());
  }
  void set_alive(std::uint64_t n) { alive_ = n; }

  std::vector<double> step_s;                   // step k (1-based) at index k - 1
  std::vector<double> step_cpu_s;               // its process CPU time (the loop runs on one thread)
  std::vector<std::uint64_t> objects_at_start;  // objects alive when that step began
  std::uint64_t before_by_fragments[3] = {0, 0, 0}, after_by_fragments[3] = {0, 0, 0};
  std::uint64_t fragments = 0;

 private:
  double breakup_time_s_;
  double last_ = 0.0, last_cpu_ = 0.0;
  std::uint64_t alive_ = 0;
};

// leo-19647 for `steps` steps of 30 s on one thread with kappa 10 tracking and `breakup` at the end of
// step `at`; every step timed.
struct BreakupRun {
  std::unique_ptr<StepTimingSink> sink;
  RunSummary summary;
};
BreakupRun run_with_breakup(const Population& leo, std::int64_t steps, std::int64_t at, double lc_min,
                            const ScheduledBreakup& breakup, bool detection) {
  SimulationConfig config;
  config.start_epoch = leo19647_epoch();
  config.force_model.srp = false;
  config.force_model.atmosphere = AtmosphereModel::kExponentialFit;
  config.dt_s = 30.0;
  config.duration_s = static_cast<double>(steps) * config.dt_s;
  config.threads = 1;
  config.scan_steps_at_once = 1;
  config.checkpoint_every_steps = 0;
  config.checkpoint_every_wall_s = 0.0;
  config.progress_every_steps = 1;
  config.conjunctions_enabled = detection;
  config.conjunctions.kappa_max = 10.0;
  config.breakups.enabled = true;
  config.breakups.min_characteristic_length_m = lc_min;
  config.breakups.scheduled = {breakup};
  config.breakups.scheduled[0].step = at;
  auto propagator = std::make_unique<SymplecticPropagator>(config.force_model, config.start_epoch,
                                                           config.integrator, nullptr);
  propagator->set_threads(1);
  BreakupRun out;
  out.sink = std::make_unique<StepTimingSink>(static_cast<double>(at) * config.dt_s);
  out.sink->set_alive(leo.size());
  Simulation simulation(config, leo, default_parts(config, std::move(propagator)));
  RunControl control;
  out.sink->start();
  out.summary = simulation.run(*out.sink, control);
  return out;
}

// Median of the step times of steps first..last (1-based, inclusive).
double median_steps(const std::vector<double>& step_s, std::int64_t first, std::int64_t last) {
  std::vector<double> v(step_s.begin() + (first - 1), step_s.begin() + last);
  return median(v);
}

// ns per object-step over steps first..last (1-based): wall (or CPU) time over objects alive at each
// step's start.
double ns_per_object_step(const StepTimingSink& s, std::int64_t first, std::int64_t last, bool cpu = false) {
  double time = 0.0, object_steps = 0.0;
  for (std::int64_t k = first; k <= last; ++k) {
    time += (cpu ? s.step_cpu_s : s.step_s)[static_cast<std::size_t>(k - 1)];
    object_steps += static_cast<double>(s.objects_at_start[static_cast<std::size_t>(k - 1)]);
  }
  return time * 1e9 / object_steps;
}

// Peak resident memory since the last reset [bytes]: VmHWM of /proc/self/status (0 where unreadable).
std::int64_t peak_rss_bytes() {
  std::ifstream status("/proc/self/status");
  std::string key;
  while (status >> key) {
    if (key == "VmHWM:") {
      std::int64_t kb = 0;
      status >> kb;
      return kb * 1024;
    }
    status.ignore(1 << 20, '\n');
  }
  return 0;
}

// Resets the peak (writing 5 to /proc/self/clear_refs, Linux 4.0 on); false where it cannot.
bool reset_peak_rss() {
  std::ofstream clear("/proc/self/clear_refs");
  clear << "5";
  return static_cast<bool>(clear);
}

// The model alone, on one thread into a reused cloud (`repeats` events; the median) and into a fresh one.
void measure_generation(BreakupEvent event, int repeats, JsonLine& line) {
  // The cloud's arrays are allocated (and their pages touched) once, before timing; each repeat
  // regenerates into them. A fresh cloud per event adds the allocation (fresh_*).
  FragmentCloud cloud;
  generate_fragments(event, cloud);
  std::vector<double> rates, cpu_rates, fresh_rates;
  std::size_t fragments = 0;
  double checksum = 0.0;
  for (int rep = 0; rep < repeats; ++rep) {
    event.event_id = static_cast<std::uint64_t>(rep);
    const double t0 = now_s(), c0 = process_cpu_s();
    generate_fragments(event, cloud);
    const double wall = now_s() - t0, cpu = process_cpu_s() - c0;
    const double f0 = now_s();
    const FragmentCloud fresh = generate_fragments(event);
    fresh_rates.push_back(static_cast<double>(fresh.drawn_count) / (now_s() - f0));
    fragments = cloud.drawn_count;
    rates.push_back(static_cast<double>(cloud.drawn_count) / wall);
    cpu_rates.push_back(static_cast<double>(cloud.drawn_count) / cpu);
    checksum += cloud.fragment_mass_kg;
    std::fprintf(stderr, "repeat %d: %zu fragments drawn, %zu kept, %.4f s, %.3g fragments/s\n", rep,
                 static_cast<std::size_t>(cloud.drawn_count), cloud.size(), wall, rates.back());
  }
  line.add("fragments", static_cast<std::int64_t>(fragments))
      .add("fragments_per_s", median(rates))
      .add("fragments_per_cpu_s", median(cpu_rates))
      .add("fresh_cloud_fragments_per_s", median(fresh_rates))
      .add("checksum_mass_kg", checksum);
}

// With detection: each step after the insertion, its wall time and the objects it began with, and the
// peak RSS of the run. The first separation_s / dt steps hold the young cloud (its pairs never reach the
// narrow phase, but its boxes all overlap); the steps after them screen every pair.
void add_insert_detection(const StepTimingSink& s, std::int64_t insert_step, std::int64_t after_steps,
                          std::int64_t rss_before, JsonLine& line) {
  const auto index = [&](std::int64_t k) { return static_cast<std::size_t>(insert_step + k - 1); };
  const auto separation_steps = static_cast<std::int64_t>(BreakupSettings{}.separation_s / 30.0);  // 20
  std::vector<double> young, young_cpu, parted, parted_cpu;
  for (std::int64_t k = 1; k <= after_steps; ++k) {
    const double wall = s.step_s[index(k)], cpu = s.step_cpu_s[index(k)];
    const std::string key = "insert_detect_step_" + std::to_string(k);
    line.add(key + "_s", wall).add(key + "_cpu_s", cpu);
    (k <= separation_steps ? young : parted).push_back(wall);
    (k <= separation_steps ? young_cpu : parted_cpu).push_back(cpu);
    std::fprintf(
        stderr, "insert, detection: step %lld after the breakup (%llu objects): %.4f s, %.4f CPU s\n",
        static_cast<long long>(k), static_cast<unsigned long long>(s.objects_at_start[index(k)]), wall, cpu);
  }
  const auto sum = [](const std::vector<double>& v) { return std::accumulate(v.begin(), v.end(), 0.0); };
  line.add("insert_detect_separation_steps", separation_steps)
      .add("insert_detect_young_median_s", median(young))
      .add("insert_detect_young_median_cpu_s", median(young_cpu))
      .add("insert_detect_young_max_s", *std::max_element(young.begin(), young.end()))
      .add("insert_detect_young_total_s", sum(young))
      .add("insert_detect_young_total_cpu_s", sum(young_cpu));
  if (!parted.empty())
    line.add("insert_detect_parted_median_s", median(parted))
        .add("insert_detect_parted_median_cpu_s", median(parted_cpu));
  line.add("insert_rss_before_bytes", rss_before).add("insert_peak_rss_bytes", peak_rss_bytes());
}

// ~100,000 fragments (Lc >= 1 cm) scheduled into leo-19647 at the end of step insert_step.
bool measure_insert(const Population& leo, const ScheduledBreakup& collision, const BreakupEvent& event,
                    std::int64_t insert_step, std::int64_t insert_after, bool detection, JsonLine& line) {
  // N(>= Lc) = 0.1 M^0.75 Lc^-1.71 = 100,000 at Lc = 1 cm: M = (1e6 Lc^1.71)^(4/3) = 2,754 kg; a
  // 1,000 kg projectile on the rest is catastrophic (E_p = 3.9e4 J/g at 11.7 km/s).
  const double lc = 0.01;
  const double total_mass = std::pow(1e5 / (0.1 * std::pow(lc, -1.71)), 4.0 / 3.0) + 1.0;
  ScheduledBreakup big = collision;
  big.masses_kg = {1000.0, total_mass - 1000.0};
  line.add("insert_detection", static_cast<std::int64_t>(detection ? 1 : 0));
  const std::int64_t rss_before = peak_rss_bytes();
  if (detection && !reset_peak_rss()) std::fprintf(stderr, "insert: cannot reset the peak RSS\n");
  BreakupRun r;
  try {
    r = run_with_breakup(leo, insert_step + insert_after, insert_step, lc, big, detection);
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "kessler-bench breakup: insert run: out of memory\n");
    line.add("insert_out_of_memory", static_cast<std::int64_t>(1));
    return false;
  }
  const auto& st = r.sink->step_s;
  const double before = median_steps(st, 2, insert_step - 1);  // step 1 warms up
  const double after = median_steps(st, insert_step + 1, insert_step + insert_after);
  const double insert_s = st[static_cast<std::size_t>(insert_step - 1)] - before;
  // The same in CPU time: the loop runs on one thread, so other programs on the cores do not count.
  const auto& ct = r.sink->step_cpu_s;
  const double before_cpu = median_steps(ct, 2, insert_step - 1);
  const double after_cpu = median_steps(ct, insert_step + 1, insert_step + insert_after);
  const double insert_cpu_s = ct[static_cast<std::size_t>(insert_step - 1)] - before_cpu;
  std::fprintf(stderr,
               "insert: %llu fragments at the end of step %lld: that step %.4f s, median step before %.4f s, "
               "after %.4f s (%llu objects)\n",
               static_cast<unsigned long long>(r.sink->fragments), static_cast<long long>(insert_step),
               st[static_cast<std::size_t>(insert_step - 1)], before, after,
               static_cast<unsigned long long>(r.sink->objects_at_start.back()));
  // The model alone on the same masses and speed into a fresh cloud (as the core generates it): the rest
  // of insert_s is the population's side (parents out, fragments appended).
  BreakupEvent alone = event;
  alone.event_id = 0;
  alone.min_characteristic_length_m = lc;
  alone.parents[0].mass_kg = 1000.0;
  alone.parents[1].mass_kg = total_mass - 1000.0;
  const double g0 = now_s();
  const FragmentCloud generated = generate_fragments(alone);
  const double generate_s = now_s() - g0;
  std::fprintf(stderr, "insert: the model alone, %zu fragments into a fresh cloud: %.4f s\n",
               generated.size(), generate_s);
  const auto* a = r.sink->after_by_fragments;
  line.add("insert_out_of_memory", static_cast<std::int64_t>(0))
      .add("insert_fragments", static_cast<std::int64_t>(r.sink->fragments))
      .add("insert_generate_s", generate_s)
      .add("insert_mass_kg", total_mass)
      .add("insert_s", insert_s)
      .add("insert_step_before_s", before)
      .add("insert_step_after_s", after)
      .add("insert_steps", insert_s / after)
      .add("insert_cpu_s", insert_cpu_s)
      .add("insert_step_before_cpu_s", before_cpu)
      .add("insert_step_after_cpu_s", after_cpu)
      .add("insert_steps_cpu", insert_cpu_s / after_cpu)
      .add("insert_conjunctions_after", static_cast<std::int64_t>(a[0] + a[1] + a[2]))
      .add("insert_conjunctions_after_fragment_fragment", static_cast<std::int64_t>(a[2]));
  if (detection) add_insert_detection(*r.sink, insert_step, insert_after, rss_before, line);
  return true;
}

// Iridium 33 / Cosmos 2251 (560 kg + 950 kg at 11.7 km/s, Lc >= 10 cm: 1,242 fragments) at the end of
// step growth_steps, then as many steps again.
void measure_growth(const Population& leo, const ScheduledBreakup& collision, std::int64_t growth_steps,
                    JsonLine& line) {
  ScheduledBreakup iridium = collision;
  iridium.masses_kg = {560.0, 950.0};
  const BreakupRun r = run_with_breakup(leo, 2 * growth_steps, growth_steps, 0.10, iridium, true);
  const StepTimingSink& s = *r.sink;
  const double before = ns_per_object_step(s, 2, growth_steps - 1);
  const double after = ns_per_object_step(s, growth_steps + 1, 2 * growth_steps);
  const double before_cpu = ns_per_object_step(s, 2, growth_steps - 1, true);
  const double after_cpu = ns_per_object_step(s, growth_steps + 1, 2 * growth_steps, true);
  const auto* a = s.after_by_fragments;
  const auto* b = s.before_by_fragments;
  std::fprintf(
      stderr,
      "growth: %llu fragments at the end of step %lld; %.1f ns/object-step before, %.1f after (%.3fx); "
      "encounters before %llu, after %llu (catalog-catalog %llu, fragment-catalog %llu, "
      "fragment-fragment %llu)\n",
      static_cast<unsigned long long>(s.fragments), static_cast<long long>(growth_steps), before, after,
      after / before, static_cast<unsigned long long>(b[0] + b[1] + b[2]),
      static_cast<unsigned long long>(a[0] + a[1] + a[2]), static_cast<unsigned long long>(a[0]),
      static_cast<unsigned long long>(a[1]), static_cast<unsigned long long>(a[2]));
  line.add("growth_fragments", static_cast<std::int64_t>(s.fragments))
      .add("growth_steps", growth_steps)
      .add("ns_per_object_step_before", before)
      .add("ns_per_object_step_after", after)
      .add("after_over_before", after / before)
      .add("cpu_ns_per_object_step_before", before_cpu)
      .add("cpu_ns_per_object_step_after", after_cpu)
      .add("cpu_after_over_before", after_cpu / before_cpu)
      .add("breakup_step_s", s.step_s[static_cast<std::size_t>(growth_steps - 1)])
      .add("conjunctions_before", static_cast<std::int64_t>(b[0] + b[1] + b[2]))
      .add("conjunctions_after", static_cast<std::int64_t>(a[0] + a[1] + a[2]))
      .add("conjunctions_after_catalog_catalog", static_cast<std::int64_t>(a[0]))
      .add("conjunctions_after_fragment_catalog", static_cast<std::int64_t>(a[1]))
      .add("conjunctions_after_fragment_fragment", static_cast<std::int64_t>(a[2]));
}

int bench_breakup(int argc, char** argv) {
  Args args(argc, argv);
  args.allow_only({"--lc-min", "--threads", "--repeats", "--skip-insert", "--skip-growth", "--insert-step",
                   "--insert-after", "--growth-steps", "--insert-detection"});
  const double lc_min = args.get_double("--lc-min", 0.01);
  const int threads = static_cast<int>(args.get_int("--threads", 1));
  const int repeats = static_cast<int>(args.get_int("--repeats", 3));
  const bool do_insert = !args.has("--skip-insert"), do_growth = !args.has("--skip-growth");
  const bool insert_detection = args.has("--insert-detection");
  const std::int64_t insert_step = args.get_int("--insert-step", 30);
  const std::int64_t insert_after = args.get_int("--insert-after", insert_detection ? 25 : 5);
  const std::int64_t growth_steps = args.get_int("--growth-steps", 300);
  if (threads < 1 || repeats < 1 || insert_step < 3 || insert_after < 1 || growth_steps < 3) {
    std::fprintf(stderr,
                 "kessler-bench breakup: --threads, --repeats, --insert-after must be positive, "
                 "--insert-step and --growth-steps at least 3\n");
    return 2;
  }
  omp_set_num_threads(threads);

  BreakupEvent event;
  event.kind = BreakupKind::kCollision;
  event.min_characteristic_length_m = lc_min;
  event.seed = 20090210;
  BreakupParent projectile{1, 560.0, 1.5, BreakupObjectClass::kSpacecraft, {7.0e6, 0, 0}, {0, 7500.0, 0}};
  BreakupParent target{2, 950.0, 2.0, BreakupObjectClass::kSpacecraft, {7.0e6, 0, 0}, {0, 7500.0, 0}};
  projectile.velocity_m_s[2] = 11700.0;
  event.parents = {projectile, target};
  JsonLine line;
  line.add("benchmark", std::string("breakup"))
      .add("lc_min_m", lc_min)
      .add("threads", static_cast<std::int64_t>(threads))
      .add("repeats", static_cast<std::int64_t>(repeats));
  measure_generation(event, repeats, line);

  Population leo;
  if (do_insert || do_growth) {
    try {
      leo = load_leo19647(default_datasets_dir() + "/leo-19647");
      validate_for_propagation(leo);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "kessler-bench breakup: leo-19647: %s\n", e.what());
      return 1;
    }
  }
  ScheduledBreakup collision;
  collision.kind = BreakupKind::kCollision;
  collision.object_ids = {kParentA, kParentB};
  collision.impact_speed_m_s = 11700.0;
  try {
    if (do_insert &&
        !measure_insert(leo, collision, event, insert_step, insert_after, insert_detection, line)) {
      line.print();
      return 1;
    }
    if (do_growth) measure_growth(leo, collision, growth_steps, line);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "kessler-bench breakup: %s\n", e.what());
    return 1;
  }
  line.print();
  return 0;
}

}  // namespace

KESSLER_BENCH("breakup",
              "NASA breakup model: fragments generated per second, catastrophic reference collision "
              "(--lc-min 0.01, --threads 1, --repeats 3); then leo-19647 runs with scheduled breakups: "
              "insert_s of ~100,000 fragments (--skip-insert, --insert-step 30, --insert-after 5; "
              "--insert-detection: each step after it with detection, peak RSS) and ns per object-step "
              "before and after Iridium/Cosmos (--skip-growth, --growth-steps 300)",
              bench_breakup);

}  // namespace kessler::bench
