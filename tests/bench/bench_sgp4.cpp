// kessler-bench sgp4: SGP4 throughput on the real catalog's LEO objects (catalog-2022 after the paper's
// filters, ingested to 2022-01-01), repeated cyclically up to --objects. Each repeat propagates every
// object to --times instants one minute apart; the figure is the median over --repeats.
//   --objects N (default 100000)  --times M (default 10)  --threads T (default 1)  --repeats R (5)
//   --path batch|scalar (default batch: the vector path used by the propagator)
#include <omp.h>

#include <cstdio>
#include <ctime>
#include <string>
#include <vector>

#include "core/catalog/bundled_datasets.hpp"
#include "core/sgp4/sgp4_batch.hpp"
#include "tests/bench/bench.hpp"

namespace kessler::bench {
namespace {

int bench_sgp4(int argc, char** argv) {
  Args args(argc, argv);
  args.allow_only({"--objects", "--times", "--threads", "--repeats", "--path"});
  const auto objects = static_cast<std::size_t>(args.get_int("--objects", 100000));
  const auto times = static_cast<std::size_t>(args.get_int("--times", 10));
  const int threads = static_cast<int>(args.get_int("--threads", 1));
  const int repeats = static_cast<int>(args.get_int("--repeats", 5));
  const std::string path = args.get("--path", "batch");
  if (objects == 0 || times == 0 || threads < 1 || repeats < 1 || (path != "batch" && path != "scalar")) {
    std::fprintf(stderr,
                 "kessler-bench sgp4: --objects, --times, --threads, --repeats must be positive; --path "
                 "batch|scalar\n");
    return 2;
  }
  omp_set_num_threads(threads);

  std::string error;
  auto input = load_bundled_catalog("catalog-2022", default_datasets_dir(), &error);
  if (!input) {
    std::fprintf(stderr, "kessler-bench sgp4: %s\n", error.c_str());
    return 1;
  }
  const UtcEpoch start = UtcEpoch::from_calendar(2022, 1, 1, 0, 0, 0);
  const IngestResult ingest = ingest_catalog(*input, IngestRules{}, start, 1);
  std::vector<Sgp4Record> records;
  std::vector<double> offset_min;
  records.reserve(objects);
  for (std::size_t i = 0; i < objects; ++i) {
    const std::size_t k = i % ingest.sgp4_records.size();
    records.push_back(ingest.sgp4_records[k]);
    offset_min.push_back(start.seconds_since(ingest.elements[k].epoch) / 60.0);
  }
  const Sgp4Batch batch(records);
  std::vector<double> minutes(objects), x(objects), y(objects), z(objects), vx(objects), vy(objects),
      vz(objects);
  std::vector<Sgp4Error> errors(objects);
  const Sgp4BatchOutput out{x.data(),  y.data(), z.data(), vx.data(),    vy.data(),
                            vz.data(), 1000.0,   1000.0,   errors.data()};

  // Wall time and process CPU time: on a shared machine the CPU time per propagation is the steadier
  // per-core cost (it does not count the time other processes hold the core).
  std::vector<double> walls, cpus;
  double checksum = 0.0;
  for (int rep = 0; rep < repeats; ++rep) {
    const double t0 = now_s();
    const std::clock_t c0 = std::clock();
    for (std::size_t k = 0; k < times; ++k) {
      for (std::size_t i = 0; i < objects; ++i) minutes[i] = offset_min[i] + static_cast<double>(k);
      if (path == "batch") {
        batch.propagate_all(minutes.data(), out);
      } else {
#pragma omp parallel for schedule(static)
        for (std::size_t i = 0; i < objects; ++i) {
          const Sgp4State s = sgp4_propagate(records[i], minutes[i]);
          x[i] = s.position_km[0] * 1000.0;
        }
      }
    }
    walls.push_back(now_s() - t0);
    cpus.push_back(static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC);
    checksum += x[objects / 2];
  }
  const double wall = median(walls);
  const double rate = static_cast<double>(objects * times) / wall;
  const double cpu = median(cpus);
  const double cpu_rate = static_cast<double>(objects * times) / cpu;
  std::printf(
      "sgp4 %s: %zu objects (%zu near-Earth) x %zu times, %d threads: median %.4f s of %d repeats, "
      "%.3g propagations/s (%.1f ns each per thread)\n",
      path.c_str(), objects, batch.near_earth_count(), times, threads, wall, repeats, rate,
      1e9 * threads / rate);
  JsonLine()
      .add("benchmark", std::string("sgp4"))
      .add("path", path)
      .add("objects", static_cast<std::int64_t>(objects))
      .add("times", static_cast<std::int64_t>(times))
      .add("threads", static_cast<std::int64_t>(threads))
      .add("repeats", static_cast<std::int64_t>(repeats))
      .add("wall_s", wall)
      .add("propagations_per_s", rate)
      .add("propagations_per_s_per_thread", rate / threads)
      .add("cpu_s", cpu)
      .add("propagations_per_cpu_s", cpu_rate)
      .add("checksum_m", checksum)
      .print();
  return 0;
}

}  // namespace

KESSLER_BENCH("sgp4", "SGP4 propagations per second on the real catalog's LEO objects", bench_sgp4);

}  // namespace kessler::bench
