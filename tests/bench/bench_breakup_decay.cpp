// kessler-bench breakup-decay: the Iridium 33 / Cosmos 2251 cloud from 2009-02-10 to --to (default
// 2026-03-01), through the core loop, and how many fragments of each parent are still on orbit at each
// year boundary and at the end.
//
// The parents come from their last element sets before the collision (tests/data/iridium_cosmos/, as
// tests/breakup/iridium_cosmos_test.cpp reads them), moved by SGP4 to the start: one step of --dt before
// the time of closest approach that test finds (16:55:59.796 UTC). Iridium 33 (NORAD 24946) 560 kg, 1.5 m;
// Cosmos 2251 (22675) 950 kg, 2.0 m (the radius is half the size; drag Cd A/m with Cd 2.2 and A = pi r^2).
// A ScheduledBreakup of kind kCollision at the end of step 1 (the closest approach) with masses_kg
// {560, 950} breaks them up with the NASA Standard Breakup Model at Lc >= --lc-min (default 10 cm);
// numerical propagator, default force model (J2, C22/S22, drag on the static density table, SRP with
// shadow), burn-up at 150 km, conjunctions off, steps of --dt (default 60 s), --threads (default 1).
// Each fragment's parent is taken from the BreakupReport's fragments, each burn-up's time from the
// BurnUp events: a fragment is on orbit at t when it has not burnt up by t.
// --atmosphere fit takes leo-19647's 4-term density fit instead of the table (about 1/9 of its density at
// 400 km: a lower-activity atmosphere), to see how far the counts follow the atmosphere.
//   --to ISO8601  --dt S  --lc-min M  --threads T  --seed S  --tle PATH  --atmosphere table|fit
#include <omp.h>

#include <cstdio>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "core/catalog/tle.hpp"
#include "core/integration/symplectic_propagator.hpp"
#include "core/sgp4/sgp4.hpp"
#include "core/simulation/breakups.hpp"
#include "core/simulation/simulation.hpp"
#include "core/simulation/simulation_parts.hpp"
#include "tests/bench/bench.hpp"

namespace kessler::bench {
namespace {

constexpr ObjectId kIridium = 24946, kCosmos = 22675;
constexpr double kPi = 3.14159265358979323846;

// Collects each fragment's parent and each burn-up's time; prints progress about every simulated year.
class DecaySink final : public EventSink {
 public:
  void on_encounter(std::uint64_t, const Encounter&) override {}
  void on_burn_up(std::uint64_t, const BurnUp& b) override { burn_up_s[b.id] = b.time_s; }
  void on_progress(std::uint64_t, const Progress& p) override {
    std::fprintf(stderr, "day %.0f: %llu objects, %.0f s wall\n", p.sim_time_s / 86400.0,
                 static_cast<unsigned long long>(p.objects_alive), p.wall_s);
  }
  void on_breakup(std::uint64_t, const BreakupReport& b) override {
    for (const FragmentReport& f : b.fragments) parent[f.id] = f.parent_id;
    breakup_time_s = b.time_s;
    catastrophic = b.catastrophic;
    specific_energy_j_per_g = b.specific_energy_j_per_g;
  }
  void on_checkpoint(std::uint64_t, std::int64_t, const std::string&) override {}
  void on_finished(const RunSummary&) override {}
  void on_failed(const std::string& reason) override {
    std::fprintf(stderr, "kessler-bench breakup-decay: run failed: %s\n", reason.c_str());
  }

  std::map<ObjectId, ObjectId> parent;   // fragment id -> parent id
  std::map<ObjectId, double> burn_up_s;  // object id -> burn-up time [s since the start]
  double breakup_time_s = 0.0, specific_energy_j_per_g = 0.0;
  bool catastrophic = false;
};

// Iridium 33 and Cosmos 2251 at `start` (TEME), from the element sets in `path`.
Population parents_at(const std::string& path, const UtcEpoch& start) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot open " + path);
  std::stringstream text;
  text << in.rdbuf();
  const ElementSetText parsed = parse_tle_text(text.str(), {}, path);
  if (parsed.sets.size() != 2 || !parsed.problems.empty())
    throw std::runtime_error(path + ": expected two sets");
  Population p;
  for (const ElementSetEntry& set : parsed.sets) {
    const MeanElements& el = set.elements;
    const bool iridium = el.catalog_number == kIridium;
    if (!iridium && el.catalog_number != kCosmos) throw std::runtime_error(path + ": unexpected object");
    const Sgp4State st = sgp4_propagate(sgp4_initialise(el), start.seconds_since(el.epoch) / 60.0);
    if (st.error != Sgp4Error::kNone) throw std::runtime_error("SGP4 failed");
    ObjectRecord r;
    r.id = el.catalog_number;
    r.name = iridium ? "IRIDIUM 33" : "COSMOS 2251";
    for (int i = 0; i < 3; ++i) {
      r.position_m[i] = st.position_km[i] * 1e3;
      r.velocity_m_s[i] = st.velocity_km_s[i] * 1e3;
    }
    r.radius_m = iridium ? 0.75 : 1.0;
    r.mass_kg = iridium ? 560.0 : 950.0;
    r.srp_area_to_mass_m2_kg = kPi * r.radius_m * r.radius_m / r.mass_kg;
    r.drag_area_to_mass_m2_kg = 2.2 * r.srp_area_to_mass_m2_kg;
    r.type = ObjectType::kPayload;
    p.add(r);
  }
  return p;
}

struct Remaining {
  std::int64_t iridium = 0, cosmos = 0;
};
Remaining remaining_at(const DecaySink& s, double t_s) {
  Remaining r;
  for (const auto& [id, parent] : s.parent) {
    const auto b = s.burn_up_s.find(id);
    if (b != s.burn_up_s.end() && b->second <= t_s) continue;
    ++(parent == kIridium ? r.iridium : r.cosmos);
  }
  return r;
}

// The run: from one step before the closest approach to `to`, the collision at the end of step 1.
SimulationConfig decay_config(const UtcEpoch& tca, const UtcEpoch& to, double dt_s, double lc_min,
                              int threads, std::int64_t seed) {
  SimulationConfig config;
  config.start_epoch = tca.plus_seconds(-dt_s);
  config.dt_s = dt_s;
  config.duration_s = to.seconds_since(config.start_epoch);
  config.threads = threads;
  config.conjunctions_enabled = false;
  config.checkpoint_every_steps = 0;
  config.checkpoint_every_wall_s = 0.0;
  config.progress_every_steps = static_cast<std::int64_t>(365.25 * 86400.0 / dt_s);
  config.seed = static_cast<std::uint64_t>(seed);
  config.breakups.enabled = true;
  config.breakups.min_characteristic_length_m = lc_min;
  ScheduledBreakup collision;
  collision.kind = BreakupKind::kCollision;
  collision.object_ids = {kIridium, kCosmos};
  collision.masses_kg = {560.0, 950.0};
  collision.step = 1;
  config.breakups.scheduled = {collision};
  return config;
}

int bench_breakup_decay(int argc, char** argv) {
  Args args(argc, argv);
  args.allow_only({"--to", "--dt", "--lc-min", "--threads", "--seed", "--tle", "--atmosphere"});
  const std::string to_text = args.get("--to", "2026-03-01T00:00:00Z");
  const double dt_s = args.get_double("--dt", 60.0), lc_min = args.get_double("--lc-min", 0.10);
  const int threads = static_cast<int>(args.get_int("--threads", 1));
  const std::string tle =
      args.get("--tle", std::string(KESSLER_BENCH_TEST_DATA_DIR) +
                            "/iridium_cosmos/iridium33_cosmos2251_last_pre_collision.tle");
  const std::optional<UtcEpoch> to = UtcEpoch::parse_iso8601(to_text);
  const UtcEpoch tca = UtcEpoch::from_calendar(2009, 2, 10, 16, 55, 59.796);
  if (!to || dt_s <= 0.0 || lc_min <= 0.0 || threads < 1 || to->seconds_since(tca) < 2.0 * dt_s) {
    std::fprintf(stderr, "kessler-bench breakup-decay: bad --to, --dt, --lc-min or --threads\n");
    return 2;
  }
  omp_set_num_threads(threads);

  const std::string atmosphere = args.get("--atmosphere", "table");
  if (atmosphere != "table" && atmosphere != "fit") {
    std::fprintf(stderr, "kessler-bench breakup-decay: --atmosphere table|fit\n");
    return 2;
  }
  SimulationConfig config = decay_config(tca, *to, dt_s, lc_min, threads, args.get_int("--seed", 20090210));
  if (atmosphere == "fit") config.force_model.atmosphere = AtmosphereModel::kExponentialFit;
  DecaySink sink;
  RunSummary summary;
  double wall_s = 0.0;
  std::size_t alive_at_end = 0;
  try {
    Population parents = parents_at(tle, config.start_epoch);
    auto propagator = std::make_unique<SymplecticPropagator>(config.force_model, config.start_epoch,
                                                             config.integrator, nullptr);
    propagator->set_threads(threads);
    Simulation simulation(config, std::move(parents), default_parts(config, std::move(propagator)));
    RunControl control;
    const double t0 = now_s();
    summary = simulation.run(sink, control);
    wall_s = now_s() - t0;
    alive_at_end = simulation.population().size();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "kessler-bench breakup-decay: %s\n", e.what());
    return 1;
  }
  const double end_s = static_cast<double>(summary.steps) * dt_s;
  const Remaining initial = remaining_at(sink, sink.breakup_time_s);
  const Remaining last = remaining_at(sink, end_s);
  JsonLine line;
  line.add("benchmark", std::string("breakup-decay"))
      .add("start", config.start_epoch.to_iso8601())
      .add("breakup_at", config.start_epoch.plus_seconds(sink.breakup_time_s).to_iso8601())
      .add("end", config.start_epoch.plus_seconds(end_s).to_iso8601())
      .add("dt_s", dt_s)
      .add("lc_min_m", lc_min)
      .add("atmosphere", atmosphere)
      .add("specific_energy_j_per_g", sink.specific_energy_j_per_g)
      .add("catastrophic", static_cast<std::int64_t>(sink.catastrophic ? 1 : 0))
      .add("fragments_iridium33", initial.iridium)
      .add("fragments_cosmos2251", initial.cosmos);
  for (int year = 2010;; ++year) {
    const double t = UtcEpoch::from_calendar(year, 1, 1, 0, 0, 0.0).seconds_since(config.start_epoch);
    if (t > end_s) break;
    const Remaining r = remaining_at(sink, t);
    line.add("on_orbit_" + std::to_string(year) + "_iridium33", r.iridium)
        .add("on_orbit_" + std::to_string(year) + "_cosmos2251", r.cosmos);
    std::fprintf(stderr, "%d-01-01: Iridium 33 %lld, Cosmos 2251 %lld fragments on orbit\n", year,
                 static_cast<long long>(r.iridium), static_cast<long long>(r.cosmos));
  }
  line.add("on_orbit_end_iridium33", last.iridium)
      .add("on_orbit_end_cosmos2251", last.cosmos)
      .add("objects_alive_at_end", static_cast<std::int64_t>(alive_at_end))
      .add("steps", summary.steps)
      .add("wall_s", wall_s);
  line.print();
  return 0;
}

}  // namespace

KESSLER_BENCH("breakup-decay",
              "Iridium 33 / Cosmos 2251 from their last element sets, broken up at 2009-02-10T16:56Z "
              "(Lc >= --lc-min 0.10), propagated to --to 2026-03-01 (--dt 60, --threads 1): fragments "
              "of each parent on orbit at each year boundary and at the end",
              bench_breakup_decay);

}  // namespace kessler::bench
