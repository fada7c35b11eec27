#include "tests/bench/iridium_cosmos_cloud.hpp"

#include <cstdio>
#include <fstream>
#include <memory>
#include <sstream>
#include <stdexcept>

#include "core/catalog/tle.hpp"
#include "core/integration/symplectic_propagator.hpp"
#include "core/physics/constants.hpp"
#include "core/sgp4/sgp4.hpp"
#include "core/simulation/breakups.hpp"
#include "core/simulation/simulation_parts.hpp"
#include "tests/bench/bench.hpp"

namespace kessler::bench {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Collects each fragment's parent and each burn-up's time; prints progress about every simulated year.
class CloudSink final : public EventSink {
 public:
  explicit CloudSink(CloudRun& run) : run_(run) {}
  void on_encounter(std::uint64_t, const Encounter&) override {}
  void on_burn_up(std::uint64_t, const BurnUp& b) override { run_.burn_up_s[b.id] = b.time_s; }
  void on_progress(std::uint64_t, const Progress& p) override {
    std::fprintf(stderr, "cloud day %.0f: %llu objects, %.0f s wall\n", p.sim_time_s / 86400.0,
                 static_cast<unsigned long long>(p.objects_alive), p.wall_s);
  }
  void on_breakup(std::uint64_t, const BreakupReport& b) override {
    for (const FragmentReport& f : b.fragments) {
      run_.parent[f.id] = f.parent_id;
      run_.drag_area_to_mass_m2_kg[f.id] = constants::kDefaultDragCoefficient * f.area_to_mass_m2_kg;
    }
    run_.breakup_time_s = b.time_s;
    run_.catastrophic = b.catastrophic;
    run_.specific_energy_j_per_g = b.specific_energy_j_per_g;
  }
  void on_checkpoint(std::uint64_t, std::int64_t, const std::string&) override {}
  void on_finished(const RunSummary&) override {}
  void on_failed(const std::string& reason) override { failure = reason; }
  std::string failure;

 private:
  CloudRun& run_;
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
    const bool iridium = el.catalog_number == kIridium33;
    if (!iridium && el.catalog_number != kCosmos2251) throw std::runtime_error(path + ": unexpected object");
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

SimulationConfig cloud_config(const CloudRunOptions& o) {
  SimulationConfig config;
  config.start_epoch = iridium_cosmos_tca().plus_seconds(-o.dt_s);
  config.dt_s = o.dt_s;
  config.duration_s = o.to.seconds_since(config.start_epoch);
  config.threads = o.threads;
  config.force_model = o.force_model;
  config.conjunctions_enabled = false;
  config.checkpoint_every_steps = 0;
  config.checkpoint_every_wall_s = 0.0;
  config.progress_every_steps = static_cast<std::int64_t>(365.25 * 86400.0 / o.dt_s);
  config.seed = o.seed;
  config.breakups.enabled = true;
  config.breakups.min_characteristic_length_m = o.lc_min_m;
  ScheduledBreakup collision;
  collision.kind = BreakupKind::kCollision;
  collision.object_ids = {kIridium33, kCosmos2251};
  collision.masses_kg = {560.0, 950.0};
  collision.step = 1;
  config.breakups.scheduled = {collision};
  return config;
}

}  // namespace

UtcEpoch iridium_cosmos_tca() {
  return UtcEpoch::from_calendar(2009, 2, 10, 16, 55, 59.796);
}

CloudRun run_iridium_cosmos_cloud(const CloudRunOptions& options) {
  const SimulationConfig config = cloud_config(options);
  CloudRun run;
  run.start = config.start_epoch;
  CloudSink sink(run);
  Population parents = parents_at(options.tle_path, config.start_epoch);
  auto propagator = std::make_unique<SymplecticPropagator>(config.force_model, config.start_epoch,
                                                           config.integrator, nullptr);
  propagator->set_threads(options.threads);
  Simulation simulation(config, std::move(parents), default_parts(config, std::move(propagator)));
  RunControl control;
  const double t0 = now_s();
  const RunSummary summary = simulation.run(sink, control);
  run.wall_s = now_s() - t0;
  if (!sink.failure.empty()) throw std::runtime_error("the cloud's run failed: " + sink.failure);
  run.steps = summary.steps;
  run.end_s = static_cast<double>(summary.steps) * options.dt_s;
  run.alive_at_end = simulation.population().size();
  return run;
}

CloudCounts cloud_on_orbit_at(const CloudRun& run, double t_s) {
  CloudCounts r;
  for (const auto& [id, parent] : run.parent) {
    const auto b = run.burn_up_s.find(id);
    if (b != run.burn_up_s.end() && b->second <= t_s) continue;
    ++(parent == kIridium33 ? r.iridium : r.cosmos);
  }
  return r;
}

}  // namespace kessler::bench
