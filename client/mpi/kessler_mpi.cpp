// kessler-mpi SCENARIO: one run shared out among the ranks of an MPI job (mpirun -np R kessler-mpi ...,
// srun kessler-mpi ...), printing what `kessler run SCENARIO --local` prints: the same JSON lines or
// table and the same summary, bit for bit the same events and fingerprints for any rank and thread
// count. Every rank runs the whole loop on the whole population; propagation and the conjunction scan
// are shared out among them (core/distributed/README.md). Rank 0 alone prints and writes checkpoints.
// A scenario with an ensemble runs its members over groups of ranks (mpi_ensemble.hpp); --event-stream
// hands the run to kesslerd (server/mpi_launch.hpp). Exit codes as `kessler run`: 0 finished, 1 failed
// or stopped early, 2 bad usage or scenario (on every rank).
#include <mpi.h>
#include <omp.h>
#include <sys/resource.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <iostream>
#include <memory>
#include <sstream>
#include <streambuf>
#include <string>
#include <thread>

#include "client/commands/local_run.hpp"
#include "client/mpi/mpi_ensemble.hpp"
#include "core/distributed/decomposition.hpp"
#include "core/distributed/distributed_propagator.hpp"
#include "core/distributed/distributed_scanner.hpp"
#include "core/distributed/rank_team.hpp"
#include "core/simulation/event_stream.hpp"

namespace kessler::cli {
namespace {

constexpr const char* kProgram = "kessler-mpi";

// Signals received by this rank. The ranks agree on them once per step (StopAgreement), so that every
// rank stops at the same step boundary.
std::atomic<int> g_signals{0};
extern "C" void count_signal(int) {
  g_signals.fetch_add(1);
}

// Once per step, before the propagation's gathers: the most signals any rank received, applied to every
// rank's controls as `kessler run` applies its own (the first stops after a checkpoint where there is a
// directory for it, a second cancels).
class StopAgreement {
 public:
  StopAgreement(distributed::RankTeam& team, bool resumable) : team_(team), resumable_(resumable) {}
  void set_control(RunControl* control) { control_ = control; }
  // Whether the ranks agreed to stop early (then all of them leave the loop at the same step).
  bool stopped_together() const { return stopped_together_; }
  void agree() {
    if (!control_) return;
    int signals = g_signals.load();
    {
      distributed::RankTeam::Timed timed(team_);
      MPI_Allreduce(MPI_IN_PLACE, &signals, 1, MPI_INT, MPI_MAX, team_.comm());
    }
    if (signals >= 1) stopped_together_ = true;
    if (signals >= 1 && resumable_) control_->stop_after_checkpoint = true;
    if (signals >= 2 || (signals >= 1 && !resumable_)) control_->cancel = true;
  }

 private:
  distributed::RankTeam& team_;
  bool resumable_;
  bool stopped_together_ = false;
  RunControl* control_ = nullptr;
};

// The propagator with the agreement first in each step.
class AgreeingPropagator final : public Propagator {
 public:
  AgreeingPropagator(std::unique_ptr<Propagator> inner, StopAgreement& agreement)
      : inner_(std::move(inner)), agreement_(agreement) {}
  void step(Population& population, double t_start_s, double dt_s) override {
    step_with(population, t_start_s, dt_s, StepRequest{});
  }
  void step_with(Population& population, double t_start_s, double dt_s, const StepRequest& request) override {
    agreement_.agree();
    inner_->step_with(population, t_start_s, dt_s, request);
  }
  bool takes_new_objects() const override { return inner_->takes_new_objects(); }

 private:
  std::unique_ptr<Propagator> inner_;
  StopAgreement& agreement_;
};

class NullBuffer final : public std::streambuf {
 protected:
  int overflow(int c) override { return c == traits_type::eof() ? 0 : c; }
  std::streamsize xsputn(const char*, std::streamsize n) override { return n; }
};

struct MpiOptions {
  LocalRunOptions run;
  std::string output;
  bool timing = false;
  bool event_stream = false;
  int ranks_per_member = 0;
};

// --event-stream: each line on stdin counts as a signal (kesslerd stops or cancels the run this way:
// mpirun passes its stdin on to rank 0, srun to every rank, while neither passes SIGTERM on at once).
// The end of stdin changes nothing.
void count_stop_lines() {
  std::thread([] {
    char c = 0;
    for (;;) {
      ssize_t n = ::read(0, &c, 1);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) return;
      if (c == '\n') g_signals.fetch_add(1);
    }
  }).detach();
}

// --event-stream on rank 0: the records go to what was stdout, and anything else printed to stdout
// goes to stderr, so that nothing but records reaches the stream.
int take_stdout_for_records() {
  std::cout.flush();
  const int fd = ::dup(1);
  ::dup2(2, 1);
  return fd;
}

// What the loop took on this rank, for --timing.
struct LoopFigures {
  std::size_t objects = 0;
  std::int64_t steps = 0;
  double start_s = 0.0, loop_s = 0.0;
  double mpi_s_at_start = 0.0;
  // The shared parts (null when the scenario has no scanner) and their seconds before the loop.
  const distributed::DistributedPropagator* propagator = nullptr;
  const distributed::DistributedScanner* scanner = nullptr;
  double propagate_s_at_start = 0.0, scan_s_at_start = 0.0;
  double propagate_s() const { return propagator ? propagator->compute_s() - propagate_s_at_start : 0.0; }
  double scan_s() const { return scanner ? scanner->compute_s() - scan_s_at_start : 0.0; }
};

long peak_rss_kb() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss;
}

// One JSON line on stderr (rank 0): the loop's cost per object-step and its communication share, the
// slowest rank's; the shares of the loop each rank spends on average in its part of the propagation and
// of the scan; peak memory per rank.
void report_timing(distributed::RankTeam& team, const LoopFigures& loop, int threads) {
  constexpr int kFigures = 5;
  double figures[kFigures] = {loop.loop_s, team.mpi_s() - loop.mpi_s_at_start,
                              static_cast<double>(peak_rss_kb()), loop.propagate_s(), loop.scan_s()};
  double max[kFigures] = {}, sum[kFigures] = {};
  MPI_Reduce(figures, max, kFigures, MPI_DOUBLE, MPI_MAX, 0, team.comm());
  MPI_Reduce(figures, sum, kFigures, MPI_DOUBLE, MPI_SUM, 0, team.comm());
  if (team.rank() != 0) return;
  const double object_steps = static_cast<double>(loop.objects) * static_cast<double>(loop.steps);
  auto mean_share = [&](int k) { return max[0] > 0 ? sum[k] / team.ranks() / max[0] : 0.0; };
  std::ostringstream line;
  line.precision(6);
  line << "{\"type\":\"mpi_timing\",\"ranks\":" << team.ranks() << ",\"threads_per_rank\":" << threads
       << ",\"objects\":" << loop.objects << ",\"steps\":" << loop.steps << ",\"loop_s\":" << max[0]
       << ",\"ns_per_object_step\":" << (object_steps > 0 ? max[0] * 1e9 / object_steps : 0.0)
       << ",\"mpi_s_mean\":" << sum[1] / team.ranks() << ",\"mpi_s_max\":" << max[1]
       << ",\"mpi_share_mean\":" << mean_share(1) << ",\"propagate_share_mean\":" << mean_share(3)
       << ",\"scan_share_mean\":" << mean_share(4) << ",\"peak_rss_mib_max\":" << max[2] / 1024.0
       << ",\"peak_rss_bytes_per_object_max\":"
       << (loop.objects > 0 ? max[2] * 1024.0 / static_cast<double>(loop.objects) : 0.0) << "}";
  std::cerr << line.str() << std::endl;
}

int run_ranks(MpiOptions& o, distributed::RankTeam& team) {
  OutputFormat format = OutputFormat::kTable;
  if (o.output == "json")
    format = OutputFormat::kJson;
  else if (!o.output.empty() && o.output != "table" && o.output != "text") {
    std::cerr << kProgram << ": --output must be one of table, json, got '" << o.output << "'\n";
    return kExitUsage;
  }
  LocalRunOptions& run = o.run;
  // Every rank's scan must lay out the same grid, which depends on the team's size: the ranks take the
  // smallest of their thread counts (--threads, else OpenMP's default on each node).
  int threads = run.build.threads > 0 ? run.build.threads : omp_get_max_threads();
  MPI_Allreduce(MPI_IN_PLACE, &threads, 1, MPI_INT, MPI_MIN, team.comm());
  run.build.threads = threads;
  run.local = true;
  run.program = kProgram;
  run.prints = team.rank() == 0;
  std::unique_ptr<EventStreamWriter> writer;
  if (o.event_stream) {
    // Every rank takes the same checkpoints (a stop comes after one); rank 0 writes the records.
    writer = std::make_unique<EventStreamWriter>(team.rank() == 0 ? take_stdout_for_records() : -1);
    run.sink = writer.get();
    run.sink_checkpoints = true;
    run.on_summary = [&](const RunSummary& summary) { writer->write_summary(summary); };
    run.scenario_binary = true;
    run.checkpoint_dir.clear();
    count_stop_lines();
  }
  StopAgreement agreement(team, !run.checkpoint_dir.empty() || o.event_stream);
  LoopFigures loop;
  run.build.adjust_parts = [&](const SimulationConfig& config, SimulationParts& parts) {
    auto shared = std::make_unique<distributed::DistributedPropagator>(std::move(parts.propagator), team);
    loop.propagator = shared.get();
    parts.propagator = std::make_unique<AgreeingPropagator>(std::move(shared), agreement);
    // The scanner the scenario's parts hold, on this rank's share of the grid (same settings).
    if (parts.scanner) {
      auto scanner = std::make_unique<distributed::DistributedScanner>(config.conjunctions, team);
      loop.scanner = scanner.get();
      parts.scanner = std::move(scanner);
    }
  };
  run.check_built = [&](const Simulation& sim) -> std::optional<std::string> {
    loop.objects = sim.population().size();
    loop.steps = sim.total_steps() - sim.step();
    return distributed::check_rank_count(sim.population().size(), team.ranks());
  };
  run.on_control = [&](RunControl* control) {
    agreement.set_control(control);
    if (control) {
      std::signal(SIGINT, count_signal);
      std::signal(SIGTERM, count_signal);
      // Timed from when every rank is ready: a rank whose set-up ends first would count its wait for
      // the others' in its loop (each rank reaches this once its simulation is built; a rank that fails
      // before it exits, and the launcher ends the job).
      if (o.timing) MPI_Barrier(team.comm());
      loop.start_s = MPI_Wtime();
      loop.mpi_s_at_start = team.mpi_s();
      loop.propagate_s_at_start = loop.propagate_s();
      loop.scan_s_at_start = loop.scan_s();
    } else {
      std::signal(SIGINT, SIG_DFL);
      std::signal(SIGTERM, SIG_DFL);
      loop.loop_s = MPI_Wtime() - loop.start_s;
    }
  };
  const int exit = run_local(run, format);
  // A run that failed or stopped on its own on one rank may leave others inside a collective call: end
  // them all. (Failures inside the shared work are agreed on and fail every rank at the same call, but a
  // failure of rank 0 alone, e.g. writing a checkpoint, is not.)
  if (exit == kExitFailure && team.ranks() > 1 && !agreement.stopped_together()) MPI_Abort(team.comm(), exit);
  if (exit == kExitOk && o.timing) report_timing(team, loop, run.build.threads);
  return exit;
}

// A scenario with an ensemble runs its members over groups of ranks (mpi_ensemble.hpp); any other, or
// one that cannot be read (run_ranks says why), runs on the whole team.
int run_maybe_ensemble(MpiOptions& o, distributed::RankTeam& team) {
  v1::Scenario scenario;
  if (o.event_stream || load_scenario_file(o.run.scenario_path, scenario) || !scenario.has_ensemble())
    return run_ranks(o, team);
  if (!o.run.checkpoint_dir.empty() || !o.run.resume_path.empty() || o.timing) {
    std::cerr << kProgram << ": " << o.run.scenario_path
              << ": an ensemble runs without --checkpoint-dir, --resume and --timing\n";
    return kExitUsage;
  }
  o.run.program = kProgram;
  EnsembleOptions ensemble{o.ranks_per_member, o.output == "json"};
  return run_ensemble(o.run, scenario, ensemble, team,
                      [&](LocalRunOptions& run, distributed::RankTeam& group) {
                        MpiOptions member;
                        member.run = run;
                        return run_ranks(member, group);
                      });
}

int parse_and_run(int argc, char** argv, distributed::RankTeam& team) {
  MpiOptions o;
  CLI::App app{"kessler-mpi: one scenario run shared out among MPI ranks (mpirun -np R kessler-mpi SCENARIO)",
               kProgram};
  app.add_option("SCENARIO", o.run.scenario_path, "a scenario file, YAML or JSON (see deploy/scenarios/)")
      ->required();
  app.add_option("--threads", o.run.build.threads,
                 "OpenMP threads per rank (0, the default: OpenMP's default)")
      ->option_text("T")
      ->check(CLI::Range(0, 4096));
  app.add_option("--checkpoint-dir", o.run.checkpoint_dir,
                 "rank 0 writes checkpoints into DIR (checkpoint-<step>.ckpt; the last three are kept)")
      ->option_text("DIR");
  app.add_option(
         "--resume", o.run.resume_path,
         "continue from a checkpoint of this scenario (written under any rank count, or by kessler run)")
      ->option_text("CHECKPOINT");
  app.add_option("--datasets", o.run.build.datasets_dir, "where the bundled datasets live")
      ->option_text("DIR");
  app.add_option("--traffic-plans", o.run.build.traffic_dir, "where the shipped launch plans live")
      ->option_text("DIR");
  app.add_option("--output,-o", o.output, "table (default) or json: as kessler run --local prints");
  app.add_flag("--event-stream", o.event_stream,
               "for kesslerd --mpi-launcher: SCENARIO is a serialized kessler.v1.Scenario; rank 0 writes the "
               "run's events, checkpoints and end as binary records on stdout (core/simulation/"
               "event_stream.hpp); a line on stdin stops the run after a checkpoint, a second cancels it");
  app.add_option("--ranks-per-member", o.ranks_per_member,
                 "a scenario with ensemble.members N: ranks per member (default: ranks / N, at least 1); "
                 "the members spread over the groups, member k with seed + k")
      ->option_text("K")
      ->check(CLI::Range(1, 1 << 20));
  app.add_flag("--timing", o.timing,
               "after the run, one JSON line on stderr: ns per object-step, MPI share, peak memory per rank");
  app.footer(
      "Every rank reads the scenario; rank 0 prints. Exit codes: 0 finished, 1 failed or stopped early,\n"
      "2 bad usage or scenario (more ranks than objects too).");
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return team.rank() == 0 ? app.exit(e) : kExitOk;
  } catch (const CLI::ParseError& e) {
    std::cerr << kProgram << ": " << e.what() << " (see " << kProgram << " --help)\n";
    return kExitUsage;
  }
  return run_maybe_ensemble(o, team);
}

}  // namespace
}  // namespace kessler::cli

int main(int argc, char** argv) {
  int provided = 0;
  // MPI is called from the thread that runs the loop alone, outside OpenMP regions.
  MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided);
  int exit = kessler::cli::kExitFailure;
  {
    kessler::distributed::RankTeam team(MPI_COMM_WORLD);
    // The other ranks compute the same run silently: rank 0 speaks for all of them.
    kessler::cli::NullBuffer nowhere;
    std::streambuf* out = std::cout.rdbuf();
    std::streambuf* err = std::cerr.rdbuf();
    if (team.rank() != 0) {
      std::cout.rdbuf(&nowhere);
      std::cerr.rdbuf(&nowhere);
    }
    exit = kessler::cli::parse_and_run(argc, argv, team);
    std::cout.flush();
    std::cout.rdbuf(out);
    std::cerr.rdbuf(err);
  }
  MPI_Finalize();
  return exit;
}
