// kessler-bench msis-grid: the cost of building NRLMSISE-00's force-model grid (core/physics/msis_grid.hpp),
// one UTC day at a time, with observed solar activity from --from (default 2001-11-15, solar maximum).
// A long projection builds one such day per simulated day, so this is the atmosphere's fixed cost; and
// the grid of one 120 s slot (slot_cpu_ms), built from the day's series every 120 s of simulated time.
//   --days D  --threads T  --from YYYY-MM-DD
#include <omp.h>

#include <algorithm>
#include <cstdio>
#include <iostream>

#include "core/physics/msis_grid.hpp"
#include "core/physics/space_weather.hpp"
#include "tests/bench/bench.hpp"

namespace kessler::bench {
namespace {

int run(int argc, char** argv) {
  Args args(argc, argv);
  args.allow_only({"--days", "--threads", "--from"});
  const auto days = args.get_int("--days", 3);
  const int threads = static_cast<int>(args.get_int("--threads", 1));
  const std::string from = args.get("--from", "2001-11-15");
  if (days <= 0 || threads <= 0) {
    std::cerr << "kessler-bench msis-grid: --days and --threads must be positive\n";
    return 2;
  }
  int year = 0, month = 0, day = 0;
  if (std::sscanf(from.c_str(), "%d-%d-%d", &year, &month, &day) != 3) {
    std::cerr << "kessler-bench msis-grid: --from is YYYY-MM-DD\n";
    return 2;
  }
  omp_set_num_threads(threads);
  MsisDensityGrid grid(UtcEpoch::from_calendar(year, month, day, 0, 0, 0), SolarActivitySettings{},
                       SpaceWeather::bundled());
  std::vector<double> walls, cpus;
  for (std::int64_t d = 0; d < days; ++d) {
    const double start = now_s(), cpu_start = process_cpu_s();
    grid.grid_at((static_cast<double>(d) + 0.5) * 86400.0);  // the day's build and one slot
    walls.push_back(now_s() - start);
    cpus.push_back(process_cpu_s() - cpu_start);
    std::printf("day %lld: %.3f s wall, %.3f s cpu\n", static_cast<long long>(d + 1), walls.back(),
                cpus.back());
  }
  // A slot's grid (the series summed at one UT), as the force model asks for every 120 s of simulated time.
  std::vector<double> slot_cpus;
  for (int k = 1; k <= 20; ++k) {
    const double cpu_start = process_cpu_s();
    grid.grid_at((static_cast<double>(days - 1) + 0.5) * 86400.0 + k * msis_grid::kSlot_s);
    slot_cpus.push_back(process_cpu_s() - cpu_start);
  }
  JsonLine()
      .add("benchmark", std::string("msis-grid"))
      .add("days", days)
      .add("threads", static_cast<std::int64_t>(threads))
      .add("from", from)
      .add("wall_s_per_day", median(walls))
      .add("wall_min_s_per_day", *std::min_element(walls.begin(), walls.end()))
      .add("cpu_s_per_day", median(cpus))
      .add("slot_cpu_ms", median(slot_cpus) * 1e3)
      .print();
  return 0;
}

}  // namespace

KESSLER_BENCH("msis-grid",
              "build NRLMSISE-00's force-model grid for --days D (one per UTC day); --threads T "
              "--from YYYY-MM-DD",
              run);

}  // namespace kessler::bench
