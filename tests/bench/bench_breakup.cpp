// kessler-bench breakup: NASA Standard Breakup Model generation speed for the catastrophic reference
// collision (560 kg + 950 kg spacecraft at 11.7 km/s) down to --lc-min (default 1 cm: about 88,000
// fragments). Each repeat generates the whole cloud (event id = repeat); the figure is the median.
//   --lc-min M (default 0.01)  --threads T (default 1)  --repeats R (default 3)
#include <omp.h>

#include <cstdio>
#include <vector>

#include "core/breakup/fragment_cloud.hpp"
#include "tests/bench/bench.hpp"

namespace kessler::bench {
namespace {

int bench_breakup(int argc, char** argv) {
  Args args(argc, argv);
  args.allow_only({"--lc-min", "--threads", "--repeats"});
  const double lc_min = args.get_double("--lc-min", 0.01);
  const int threads = static_cast<int>(args.get_int("--threads", 1));
  const int repeats = static_cast<int>(args.get_int("--repeats", 3));
  if (threads < 1 || repeats < 1) {
    std::fprintf(stderr, "kessler-bench breakup: --threads and --repeats must be positive\n");
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

  // Generation alone: the cloud's arrays are allocated (and their pages touched) once, before timing;
  // each repeat regenerates into them. A fresh cloud per event adds the allocation (fresh_*).
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
  JsonLine line;
  line.add("benchmark", std::string("breakup"))
      .add("lc_min_m", lc_min)
      .add("threads", static_cast<std::int64_t>(threads))
      .add("repeats", static_cast<std::int64_t>(repeats))
      .add("fragments", static_cast<std::int64_t>(fragments))
      .add("fragments_per_s", median(rates))
      .add("fragments_per_cpu_s", median(cpu_rates))
      .add("fresh_cloud_fragments_per_s", median(fresh_rates))
      .add("checksum_mass_kg", checksum);
  line.print();
  return 0;
}

}  // namespace

KESSLER_BENCH("breakup",
              "NASA breakup model: fragments generated per second, catastrophic reference collision "
              "(--lc-min 0.01, --threads 1, --repeats 3)",
              bench_breakup);

}  // namespace kessler::bench
