// kessler-bench snapshot: what population snapshots cost a run. Builds a scenario's population (the
// paper's by default), times --steps of its loop (the run's CPU time per simulated day), then takes
// --snapshots snapshots of the population and stores them in a fresh database through the Store's
// writer (encoded and deflated there), and the same blobs appended to a flat file for comparison.
// Reports the stored size of the series (and of a 20-year series at one snapshot per 10 days) and the
// snapshots' CPU time against the run's time between two snapshots.
#if defined(KESSLER_WITH_SERVER)
#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iostream>

#include "core/scenario/run_builder.hpp"
#include "server/snapshot_codec.hpp"
#include "server/store.hpp"
#include "tests/bench/bench.hpp"

namespace kessler::bench {
namespace {

// CPU seconds of the calling thread: the store's writer works beside it.
double thread_cpu_s() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

std::uint64_t file_bytes(const std::string& path) {
  struct stat st {};
  return stat(path.c_str(), &st) == 0 ? static_cast<std::uint64_t>(st.st_size) : 0;
}

int run(int argc, char** argv) {
  Args args(argc, argv);
  args.allow_only({"--scenario", "--steps", "--snapshots", "--every-days", "--dir"});
  const std::string path =
      args.get("--scenario", std::string(KESSLER_DATASETS_DIR) + "/../scenarios/paper.yaml");
  const std::int64_t steps = args.get_int("--steps", 100);
  const std::int64_t count = args.get_int("--snapshots", 100);
  const double every_days = args.get_double("--every-days", 10.0);
  const std::string dir = args.get("--dir", std::filesystem::temp_directory_path().string());
  if (steps <= 0 || count <= 0 || !(every_days > 0.0)) {
    std::cerr << "kessler-bench snapshot: --steps, --snapshots, --every-days must be positive\n";
    return 2;
  }
  v1::Scenario scenario;
  auto error = load_scenario_file(path, scenario);
  if (!error) error = validate_scenario(scenario);
  if (error) {
    std::cerr << "kessler-bench snapshot: " << path << ": " << error->message() << '\n';
    return 2;
  }
  const double dt = scenario.has_dt_s() ? scenario.dt_s() : 30.0;
  scenario.set_duration_days(static_cast<double>(steps) * dt / 86400.0);
  scenario.mutable_checkpoints()->set_every_steps(0);
  scenario.mutable_checkpoints()->set_every_wall_s(0);
  scenario.mutable_snapshots()->set_every_days(0);
  BuildOptions options;
  options.threads = 1;
  FieldError build_error;
  auto sim = build_simulation(scenario, options, &build_error);
  if (!sim) {
    std::cerr << "kessler-bench snapshot: " << build_error.message() << '\n';
    return 1;
  }
  NullSink sink;
  RunControl control;
  const double cpu0 = process_cpu_s();
  sim->run(sink, control);
  const double run_cpu_per_step = (process_cpu_s() - cpu0) / static_cast<double>(steps);
  const double run_cpu_between_snapshots = run_cpu_per_step * every_days * 86400.0 / dt;

  const std::string db = dir + "/kessler-bench-snapshot-" + std::to_string(getpid()) + ".db";
  const std::string flat = db + ".snapshots";
  double take_cpu = 0.0, encode_cpu = 0.0, file_cpu = 0.0, writer_cpu = 0.0;
  std::uint64_t raw_bytes = 0, blob_bytes = 0;
  {
    server::Store store(db);
    const std::int64_t run_id = store.create_run(scenario, 1, 0.0);
    std::ofstream file(flat, std::ios::binary);
    for (std::int64_t k = 0; k < count; ++k) {
      double t = thread_cpu_s();
      auto snapshot =
          std::make_shared<const PopulationSnapshot>(take_snapshot(sim->population(), k * 86400, 0.0));
      take_cpu += thread_cpu_s() - t;
      raw_bytes = snapshot->size() * (8 + 2 + 4 * 8);
      t = thread_cpu_s();
      const std::string blob = server::encode_snapshot(*snapshot);
      encode_cpu += thread_cpu_s() - t;
      blob_bytes = blob.size();
      t = thread_cpu_s();
      file.write(blob.data(), static_cast<std::streamsize>(blob.size()));
      file.flush();
      file_cpu += thread_cpu_s() - t;
      store.append_snapshot(run_id, std::move(snapshot));
    }
    store.flush();
    writer_cpu = store.writer_cpu_s();
  }
  const std::uint64_t db_bytes = file_bytes(db) + file_bytes(db + "-wal");
  const std::uint64_t flat_bytes = file_bytes(flat);
  for (const std::string& f : {db, db + "-wal", db + "-shm", flat}) std::remove(f.c_str());

  const double n = static_cast<double>(count);
  const double per_snapshot_cpu = take_cpu / n + writer_cpu / n;  // taken on the loop, stored by the writer
  const double series_20y = std::floor(7305.0 / every_days) + 1.0;
  std::printf("%lld objects; run %.3f s CPU per step, %.1f s between snapshots (every %g d)\n",
              static_cast<long long>(sim->population().size()), run_cpu_per_step, run_cpu_between_snapshots,
              every_days);
  std::printf(
      "per snapshot: take %.2f ms, encode %.2f ms, store (writer, encode included) %.2f ms, "
      "flat file append %.3f ms; %.0f kB raw, %.0f kB deflated\n",
      1e3 * take_cpu / n, 1e3 * encode_cpu / n, 1e3 * writer_cpu / n, 1e3 * file_cpu / n,
      static_cast<double>(raw_bytes) / 1e3, static_cast<double>(blob_bytes) / 1e3);
  JsonLine()
      .add("benchmark", std::string("snapshot"))
      .add("scenario", path)
      .add("objects", static_cast<std::int64_t>(sim->population().size()))
      .add("snapshots", count)
      .add("run_cpu_s_per_step", run_cpu_per_step)
      .add("run_cpu_s_between_snapshots", run_cpu_between_snapshots)
      .add("take_ms", 1e3 * take_cpu / n)
      .add("encode_ms", 1e3 * encode_cpu / n)
      .add("store_writer_ms", 1e3 * writer_cpu / n)
      .add("flat_file_append_ms", 1e3 * file_cpu / n)
      .add("raw_bytes_per_snapshot", static_cast<std::int64_t>(raw_bytes))
      .add("blob_bytes_per_snapshot", static_cast<std::int64_t>(blob_bytes))
      .add("db_bytes_per_snapshot", static_cast<std::int64_t>(db_bytes / static_cast<std::uint64_t>(count)))
      .add("flat_file_bytes_per_snapshot",
           static_cast<std::int64_t>(flat_bytes / static_cast<std::uint64_t>(count)))
      .add("series_20y_snapshots", static_cast<std::int64_t>(series_20y))
      .add("series_20y_db_mb", series_20y * static_cast<double>(db_bytes) / n / 1e6)
      .add("cpu_share_of_run", per_snapshot_cpu / run_cpu_between_snapshots)
      .print();
  return 0;
}

}  // namespace

KESSLER_BENCH("snapshot",
              "population snapshots: stored size of a series and CPU time against the run's; --scenario FILE "
              "(default the paper's) --steps S --snapshots N --every-days D [--dir DIR]",
              run);

}  // namespace kessler::bench

#endif  // KESSLER_WITH_SERVER
