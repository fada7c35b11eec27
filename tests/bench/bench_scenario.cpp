// kessler-bench scenario: a scenario's main loop for --steps steps, the paper's runtime breakdown
// (integrator, burn-up, grid, detection, output, checkpoint) as medians over --repeats; the population is
// built (ingested) once per repeat, outside the timing. Checkpoints off unless --checkpoint-every N.
#include <algorithm>
#include <cstdio>
#include <iostream>

#include "core/scenario/run_builder.hpp"
#include "tests/bench/bench.hpp"

namespace kessler::bench {
namespace {

class CheckpointSizeSink final : public NullSink {
 public:
  std::uint64_t checkpoint_bytes = 0;
  void on_checkpoint(std::uint64_t, std::int64_t, const std::string& bytes) override {
    checkpoint_bytes = bytes.size();
  }
};

int run(int argc, char** argv) {
  Args args(argc, argv);
  args.allow_only({"--scenario", "--steps", "--threads", "--repeats", "--checkpoint-every"});
  const std::string path =
      args.get("--scenario", std::string(KESSLER_DATASETS_DIR) + "/../scenarios/leo-19647-week.yaml");
  const std::int64_t steps = args.get_int("--steps", 100);
  const int threads = static_cast<int>(args.get_int("--threads", 1));
  const int repeats = static_cast<int>(args.get_int("--repeats", 3));
  const std::int64_t checkpoint_every = args.get_int("--checkpoint-every", 0);
  if (steps <= 0 || threads <= 0 || repeats <= 0 || checkpoint_every < 0) {
    std::cerr << "kessler-bench scenario: --steps, --threads, --repeats must be positive\n";
    return 2;
  }
  v1::Scenario scenario;
  auto error = load_scenario_file(path, scenario);
  if (!error) error = validate_scenario(scenario);
  if (error) {
    std::cerr << "kessler-bench scenario: " << path << ": " << error->message() << '\n';
    return 2;
  }
  const double dt = scenario.has_dt_s() ? scenario.dt_s() : 10.0;
  scenario.set_duration_days(static_cast<double>(steps) * dt / 86400.0);
  scenario.mutable_checkpoints()->set_every_steps(checkpoint_every);
  scenario.mutable_checkpoints()->set_every_wall_s(0);
  BuildOptions options;
  options.threads = threads;

  std::vector<double> total, integrator, burn_up, grid, detection, output, checkpoint;
  RunSummary last;
  CheckpointSizeSink sink;
  for (int rep = 0; rep < repeats; ++rep) {
    FieldError build_error;
    auto sim = build_simulation(scenario, options, &build_error);
    if (!sim) {
      std::cerr << "kessler-bench scenario: " << build_error.message() << '\n';
      return 1;
    }
    RunControl control;
    last = sim->run(sink, control);
    const PhaseTimers& t = last.timers;
    total.push_back(t.total_s);
    integrator.push_back(t.integrator_s);
    burn_up.push_back(t.burn_up_s);
    grid.push_back(t.grid_s);
    detection.push_back(t.detection_s);
    output.push_back(t.output_s);
    checkpoint.push_back(t.checkpoint_s);
    std::printf(
        "repeat %d: %.3f s (integrator %.3f, burn-up %.3f, grid %.3f, detection %.3f, output %.3f, "
        "checkpoint %.3f), %llu events\n",
        rep + 1, t.total_s, t.integrator_s, t.burn_up_s, t.grid_s, t.detection_s, t.output_s, t.checkpoint_s,
        static_cast<unsigned long long>(last.events));
  }
  const double object_steps = static_cast<double>(last.objects_initial) * static_cast<double>(last.steps);
  JsonLine()
      .add("benchmark", std::string("scenario"))
      .add("scenario", path)
      .add("objects", static_cast<std::int64_t>(last.objects_initial))
      .add("steps", last.steps)
      .add("threads", static_cast<std::int64_t>(threads))
      .add("repeats", static_cast<std::int64_t>(repeats))
      .add("events", static_cast<std::int64_t>(last.events))
      .add("total_s", median(total))
      .add("integrator_s", median(integrator))
      .add("burn_up_s", median(burn_up))
      .add("grid_s", median(grid))
      .add("detection_s", median(detection))
      .add("output_s", median(output))
      .add("checkpoint_s", median(checkpoint))
      .add("checkpoint_bytes", static_cast<std::int64_t>(sink.checkpoint_bytes))
      .add("ns_per_object_step", median(total) * threads * 1e9 / object_steps)
      .add("events_digest", last.events_digest)
      .add("state_digest", last.state_digest)
      .print();
  return 0;
}

}  // namespace

KESSLER_BENCH("scenario",
              "a scenario's main loop, per-phase medians (the paper's runtime breakdown); --scenario FILE "
              "--steps S --threads T [--repeats R --checkpoint-every N]",
              run);

}  // namespace kessler::bench
