// kessler-bench mpi: kessler-mpi's cost per object-step and its communication share on a synthetic
// population of 1-10 cm debris in LEO (300..2,000 km, radii 0.5..5 cm, the MASTER-like case MPI is for),
// on --ranks R ranks of --threads T, against one rank of R x T threads (the same cores in one process),
// the two run in turn each round. The figures are kessler-mpi's own --timing line: the step loop of the
// slowest rank, the mean share of it spent in MPI calls, the peak memory per rank and object.
// kessler-bench has no MPI itself: it starts the jobs with --mpirun (default: mpirun) and --kessler-mpi
// (default: the one beside it).
#include <stdlib.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include "tests/bench/bench.hpp"

namespace kessler::bench {
namespace {

struct MpiTiming {
  double ns_per_object_step = 0.0, mpi_share = 0.0, rss_bytes_per_object = 0.0, rss_mib = 0.0;
  double propagate_share = 0.0, scan_share = 0.0;
};

// A number after "key": in a JSON line (no nesting needed: kessler-mpi's timing line is flat).
std::optional<double> json_number(const std::string& line, const std::string& key) {
  const std::string needle = "\"" + key + "\":";
  const auto at = line.find(needle);
  if (at == std::string::npos) return std::nullopt;
  return std::strtod(line.c_str() + at + needle.size(), nullptr);
}

std::string scenario_yaml(std::int64_t objects, std::int64_t steps) {
  char duration[64];
  std::snprintf(duration, sizeof duration, "%.9f", (static_cast<double>(steps) + 0.5) * 30.0 / 86400.0);
  return "name: mpi-bench-" + std::to_string(objects) +
         "\nstart_epoch: \"2022-01-01T00:00:00Z\"\nduration_days: " + duration +
         "\ndt_s: 30\npopulation:\n  synthetic: {objects: " + std::to_string(objects) +
         ", active_fraction: 0, min_altitude_km: 300, max_altitude_km: 2000}\n  rules:\n"
         "    small_radius_mean_m: 0.025\n    small_radius_stddev_m: 0.012\n"
         "    medium_radius_mean_m: 0.025\n    medium_radius_stddev_m: 0.012\n"
         "    large_radius_mean_m: 0.025\n    large_radius_stddev_m: 0.012\n"
         "checkpoints: {every_steps: 0, every_wall_s: 0}\nprogress_every_steps: 1000000\nseed: 3\n";
}

// One job; nullopt (with the job's output on stderr) when it failed or printed no timing line.
std::optional<MpiTiming> run_job(const std::string& mpirun, const std::string& program,
                                 const std::string& dir, int ranks, int threads) {
  const std::string err = dir + "/timing.err";
  const std::string command = "OMP_NUM_THREADS=" + std::to_string(threads) + " OMP_PROC_BIND=false '" +
                              mpirun + "' -np " + std::to_string(ranks) + " --bind-to none '" + program +
                              "' '" + dir + "/scenario.yaml' --threads " + std::to_string(threads) +
                              " --output json --timing > '" + dir + "/out.jsonl' 2> '" + err + "'";
  const int status = std::system(command.c_str());
  std::ifstream in(err);
  std::string line, timing;
  while (std::getline(in, line))
    if (line.find("\"mpi_timing\"") != std::string::npos) timing = line;
  if (status != 0 || timing.empty()) {
    std::ifstream again(err);
    std::cerr << again.rdbuf() << "kessler-bench mpi: the job of " << ranks << " x " << threads
              << " failed (status " << status << ")\n";
    return std::nullopt;
  }
  MpiTiming t;
  t.ns_per_object_step = json_number(timing, "ns_per_object_step").value_or(0.0);
  t.mpi_share = json_number(timing, "mpi_share_mean").value_or(0.0);
  t.propagate_share = json_number(timing, "propagate_share_mean").value_or(0.0);
  t.scan_share = json_number(timing, "scan_share_mean").value_or(0.0);
  t.rss_bytes_per_object = json_number(timing, "peak_rss_bytes_per_object_max").value_or(0.0);
  t.rss_mib = json_number(timing, "peak_rss_mib_max").value_or(0.0);
  return t;
}

std::string beside_this_program(const std::string& name) {
  std::error_code error;
  const auto self = std::filesystem::read_symlink("/proc/self/exe", error);
  return error ? name : (self.parent_path() / name).string();
}

int run(int argc, char** argv) {
  Args args(argc, argv);
  args.allow_only({"--ranks", "--threads", "--objects", "--steps", "--repeats", "--mpirun", "--kessler-mpi"});
  const int ranks = static_cast<int>(args.get_int("--ranks", 2));
  const int threads = static_cast<int>(args.get_int("--threads", 1));
  const std::int64_t objects = args.get_int("--objects", 1000000);
  const std::int64_t steps = args.get_int("--steps", 10);
  const int repeats = static_cast<int>(args.get_int("--repeats", 3));
  const std::string mpirun = args.get("--mpirun", "mpirun");
  const std::string program = args.get("--kessler-mpi", beside_this_program("kessler-mpi"));
  if (ranks <= 0 || threads <= 0 || objects < ranks || steps <= 0 || repeats <= 0) {
    std::cerr
        << "kessler-bench mpi: --ranks, --threads, --steps, --repeats must be positive and --objects at "
           "least --ranks\n";
    return 2;
  }
  if (access(program.c_str(), X_OK) != 0) {
    std::cerr << "kessler-bench mpi: --kessler-mpi: " << program
              << " is not an executable (configure with -DKESSLER_MPI=ON)\n";
    return 2;
  }
  std::string dir = (std::filesystem::temp_directory_path() / "kessler-bench-mpi-XXXXXX").string();
  if (!mkdtemp(dir.data())) {
    std::cerr << "kessler-bench mpi: cannot make a temporary directory\n";
    return 1;
  }
  std::ofstream(dir + "/scenario.yaml") << scenario_yaml(objects, steps);
  // On one machine: oversubscribed ranks that yield their core while they wait in a collective call.
  setenv("OMPI_MCA_rmaps_base_oversubscribe", "1", 0);
  setenv("OMPI_MCA_mpi_yield_when_idle", "1", 0);
  setenv("OMPI_ALLOW_RUN_AS_ROOT", "1", 0);
  setenv("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1", 0);

  std::vector<double> one_rank, many, shares, bytes, mib, propagate_shares, scan_shares;
  for (int rep = 0; rep < repeats; ++rep) {
    auto single = run_job(mpirun, program, dir, 1, ranks * threads);
    auto split = run_job(mpirun, program, dir, ranks, threads);
    if (!single || !split) {
      std::filesystem::remove_all(dir);
      return 1;
    }
    one_rank.push_back(single->ns_per_object_step);
    many.push_back(split->ns_per_object_step);
    shares.push_back(split->mpi_share);
    propagate_shares.push_back(split->propagate_share);
    scan_shares.push_back(split->scan_share);
    bytes.push_back(split->rss_bytes_per_object);
    mib.push_back(split->rss_mib);
    std::printf("round %d: 1 x %d %.1f ns, %d x %d %.1f ns (MPI %.1f %%)\n", rep + 1, ranks * threads,
                single->ns_per_object_step, ranks, threads, split->ns_per_object_step,
                100.0 * split->mpi_share);
  }
  std::filesystem::remove_all(dir);
  const double split_ns = median(many), single_ns = median(one_rank);
  JsonLine()
      .add("benchmark", std::string("mpi"))
      .add("objects", objects)
      .add("steps", steps)
      .add("ranks", static_cast<std::int64_t>(ranks))
      .add("threads_per_rank", static_cast<std::int64_t>(threads))
      .add("repeats", static_cast<std::int64_t>(repeats))
      .add("ns_per_object_step", split_ns)
      .add("ns_per_object_step_min", *std::min_element(many.begin(), many.end()))
      .add("ns_per_object_step_max", *std::max_element(many.begin(), many.end()))
      .add("one_rank_ns_per_object_step", single_ns)
      .add("cost_vs_one_rank", single_ns > 0 ? split_ns / single_ns : 0.0)
      .add("mpi_share", median(shares))
      .add("propagate_share", median(propagate_shares))
      .add("scan_share", median(scan_shares))
      .add("peak_rss_mib_per_rank", median(mib))
      .add("peak_rss_bytes_per_object", median(bytes))
      .print();
  return 0;
}

}  // namespace

KESSLER_BENCH("mpi",
              "kessler-mpi on --ranks R x --threads T against 1 rank of R x T threads, synthetic 1-10 cm LEO "
              "debris: ns per object-step, MPI share, memory [--objects N --steps S --repeats K --mpirun "
              "PATH --kessler-mpi PATH]",
              run);

}  // namespace kessler::bench
