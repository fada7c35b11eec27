// kessler-bench breakup-decay: the Iridium 33 / Cosmos 2251 cloud from 2009-02-10 to --to (default
// 2026-03-01), through the core loop, and how many fragments of each parent are still on orbit at each
// year boundary and at the end.
//
// The run (iridium_cosmos_cloud.hpp): Lc >= --lc-min (default 10 cm), default force model (J2, C22/S22,
// drag on the static density table, SRP with shadow), steps of --dt (default 60 s), --threads (default 1).
// Each fragment's parent is taken from the BreakupReport's fragments, each burn-up's time from the
// BurnUp events: a fragment is on orbit at t when it has not burnt up by t.
// --atmosphere fit takes leo-19647's 4-term density fit instead of the table (about 1/9 of its density at
// 400 km: a lower-activity atmosphere); nrlmsise00 the NRLMSISE-00 model on observed solar activity.
//   --to ISO8601  --dt S  --lc-min M  --threads T  --seed S  --tle PATH  --atmosphere table|fit|nrlmsise00
#include <omp.h>

#include <cstdio>
#include <string>

#include "tests/bench/bench.hpp"
#include "tests/bench/iridium_cosmos_cloud.hpp"

namespace kessler::bench {
namespace {

int bench_breakup_decay(int argc, char** argv) {
  Args args(argc, argv);
  args.allow_only({"--to", "--dt", "--lc-min", "--threads", "--seed", "--tle", "--atmosphere"});
  CloudRunOptions o;
  const std::optional<UtcEpoch> to = UtcEpoch::parse_iso8601(args.get("--to", "2026-03-01T00:00:00Z"));
  o.dt_s = args.get_double("--dt", 60.0);
  o.lc_min_m = args.get_double("--lc-min", 0.10);
  o.threads = static_cast<int>(args.get_int("--threads", 1));
  o.seed = static_cast<std::uint64_t>(args.get_int("--seed", 20090210));
  o.tle_path = args.get("--tle", std::string(KESSLER_BENCH_TEST_DATA_DIR) +
                                     "/iridium_cosmos/iridium33_cosmos2251_last_pre_collision.tle");
  if (!to || o.dt_s <= 0.0 || o.lc_min_m <= 0.0 || o.threads < 1 ||
      to->seconds_since(iridium_cosmos_tca()) < 2.0 * o.dt_s) {
    std::fprintf(stderr, "kessler-bench breakup-decay: bad --to, --dt, --lc-min or --threads\n");
    return 2;
  }
  o.to = *to;
  omp_set_num_threads(o.threads);
  const std::string atmosphere = args.get("--atmosphere", "table");
  if (atmosphere == "fit") {
    o.force_model.atmosphere = AtmosphereModel::kExponentialFit;
  } else if (atmosphere == "nrlmsise00") {
    o.force_model.atmosphere = AtmosphereModel::kNrlmsise00;
  } else if (atmosphere != "table") {
    std::fprintf(stderr, "kessler-bench breakup-decay: --atmosphere table|fit|nrlmsise00\n");
    return 2;
  }
  CloudRun run;
  try {
    run = run_iridium_cosmos_cloud(o);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "kessler-bench breakup-decay: %s\n", e.what());
    return 1;
  }
  const CloudCounts initial = cloud_on_orbit_at(run, run.breakup_time_s);
  const CloudCounts last = cloud_on_orbit_at(run, run.end_s);
  JsonLine line;
  line.add("benchmark", std::string("breakup-decay"))
      .add("start", run.start.to_iso8601())
      .add("breakup_at", run.start.plus_seconds(run.breakup_time_s).to_iso8601())
      .add("end", run.start.plus_seconds(run.end_s).to_iso8601())
      .add("dt_s", o.dt_s)
      .add("lc_min_m", o.lc_min_m)
      .add("atmosphere", atmosphere)
      .add("specific_energy_j_per_g", run.specific_energy_j_per_g)
      .add("catastrophic", static_cast<std::int64_t>(run.catastrophic ? 1 : 0))
      .add("fragments_iridium33", initial.iridium)
      .add("fragments_cosmos2251", initial.cosmos);
  for (int year = 2010;; ++year) {
    const double t = UtcEpoch::from_calendar(year, 1, 1, 0, 0, 0.0).seconds_since(run.start);
    if (t > run.end_s) break;
    const CloudCounts r = cloud_on_orbit_at(run, t);
    line.add("on_orbit_" + std::to_string(year) + "_iridium33", r.iridium)
        .add("on_orbit_" + std::to_string(year) + "_cosmos2251", r.cosmos);
    std::fprintf(stderr, "%d-01-01: Iridium 33 %lld, Cosmos 2251 %lld fragments on orbit\n", year,
                 static_cast<long long>(r.iridium), static_cast<long long>(r.cosmos));
  }
  line.add("on_orbit_end_iridium33", last.iridium)
      .add("on_orbit_end_cosmos2251", last.cosmos)
      .add("objects_alive_at_end", static_cast<std::int64_t>(run.alive_at_end))
      .add("steps", run.steps)
      .add("wall_s", run.wall_s);
  line.print();
  return 0;
}

}  // namespace

KESSLER_BENCH("breakup-decay",
              "Iridium 33 / Cosmos 2251 from their last element sets, broken up at 2009-02-10T16:56Z "
              "(Lc >= --lc-min 0.10), propagated to --to 2026-03-01 (--dt 60, --threads 1, --atmosphere "
              "table|fit|nrlmsise00): fragments of each parent on orbit at each year boundary and at the end",
              bench_breakup_decay);

}  // namespace kessler::bench
