// Launches and lifecycles in the main loop (core/simulation/traffic.hpp), with the project's propagator:
// planned objects enter at their boundaries with their ids, on their planned orbits; an active payload
// keeps its altitude while a passive twin decays, and decays once its life ends; disposals move it to
// its disposal orbit; 1 and 2 threads and a resume give the same bits.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "core/integration/symplectic_propagator.hpp"
#include "core/physics/constants.hpp"
#include "core/simulation/simulation.hpp"
#include "tests/simulation/test_doubles.hpp"

namespace kessler {
namespace {

using namespace kessler::testing;

constexpr double kDay_s = 86400.0;
constexpr double kRe = constants::kEarthEquatorialRadius_m;

struct LifecycleSink : RecordingSink {
  std::vector<LifecycleReport> lifecycle;
  void on_lifecycle(std::uint64_t, const LifecycleReport& e) override { lifecycle.push_back(e); }
};

// One planned object: circular at altitude_km, 51.6 deg, launched at t_s, with `lifetime_days` (0:
// passive) and a radius/mass of high area-to-mass, so drag shows within weeks.
PlannedObject planned(double t_s, double altitude_km, double lifetime_days, std::size_t row,
                      double raan_deg) {
  PlannedObject o;
  o.epoch_offset_s = t_s;
  o.row = row;
  o.elements = elements_from_altitudes(altitude_km * 1e3, altitude_km * 1e3, 51.6 * std::numbers::pi / 180.0);
  o.elements.raan_rad = raan_deg * std::numbers::pi / 180.0;
  o.mass_kg = 20.0;
  o.radius_m = 1.0;
  o.type = ObjectType::kPayload;
  o.lifetime_s = lifetime_days * kDay_s;
  o.manoeuvres = lifetime_days > 0.0;
  return o;
}

SimulationConfig traffic_config(double days, double dt_s, int threads) {
  SimulationConfig c;
  c.dt_s = dt_s;
  c.duration_s = days * kDay_s;
  c.threads = threads;
  c.conjunctions_enabled = false;
  c.force_model = ForceModelSettings{true, true, false, true, false, false};
  c.traffic.enabled = true;
  return c;
}

struct Outcome {
  LifecycleSink sink;
  RunSummary summary;
  Population population;
};

std::unique_ptr<Outcome> run(const SimulationConfig& c, Population p = {}) {
  auto out = std::make_unique<Outcome>();
  Simulation sim(c, std::move(p),
                 std::make_unique<SymplecticPropagator>(c.force_model, c.start_epoch, c.integrator));
  RunControl control;
  out->summary = sim.run(out->sink, control);
  out->population = sim.population();
  return out;
}

double altitude_km(const Population& p, ObjectId id) {
  const auto i = p.index_of(id);
  return i ? (p.state.position(*i).norm() - kRe) / 1e3 : -1.0;
}

TEST(TrafficLoop, LaunchesEnterAtTheirBoundariesWithTheirIds) {
  SimulationConfig c = traffic_config(0.01, 10.0, 1);  // 86 steps
  c.traffic.launches = {planned(95.0, 550.0, 0.0, 0, 0.0), planned(95.0, 550.0, 0.0, 0, 10.0),
                        planned(95.0, 550.0, 0.0, 0, 20.0), planned(200.0, 700.0, 0.0, 1, 30.0)};
  const auto out = run(c);
  ASSERT_EQ(out->sink.lifecycle.size(), 2u);
  const LifecycleReport &a = out->sink.lifecycle[0], &b = out->sink.lifecycle[1];
  EXPECT_EQ(a.kind, LifecycleEventKind::kLaunch);
  EXPECT_EQ(a.time_s, 100.0);  // launched inside step 10: enters at its end
  EXPECT_EQ(a.first_id, kFirstLaunchId);
  EXPECT_EQ(a.last_id, kFirstLaunchId + 2);
  EXPECT_EQ(b.time_s, 200.0);
  EXPECT_EQ(b.row, 1u);
  ASSERT_EQ(out->population.size(), 4u);
  // On their planned orbits: circular at the planned altitude (J2 moves it by a few km), in their planes.
  for (ObjectId k = 0; k < 4; ++k) {
    const std::size_t i = *out->population.index_of(kFirstLaunchId + k);
    const Eigen::Vector3d r = out->population.state.position(i), v = out->population.state.velocity(i);
    const Eigen::Vector3d h = r.cross(v);
    EXPECT_NEAR(std::acos(h.z() / h.norm()) * 180.0 / std::numbers::pi, 51.6, 0.05);
    EXPECT_NEAR(std::atan2(h.x(), -h.y()) * 180.0 / std::numbers::pi, 10.0 * static_cast<double>(k), 0.1);
    EXPECT_NEAR((r.norm() - kRe) / 1e3, k < 3 ? 550.0 : 700.0, 15.0);
  }
  EXPECT_EQ(out->population.status[0], ObjectStatus::kPassive);
  EXPECT_EQ(out->population.type[0], ObjectType::kPayload);
  // Counted by their type, not as breakup fragments (their ids are above the fragments' range too).
  const RecordedEvent& last = out->sink.events.back();
  ASSERT_EQ(last.type, 2);
  EXPECT_EQ(last.progress.objects_by_type.payload, 4u);
  EXPECT_EQ(last.progress.objects_by_type.fragments, 0u);
}

TEST(TrafficLoop, AnActivePayloadKeepsStationUntilItsLifeEnds) {
  // Two objects at 400 km, one active for 8 days, one passive; disposal always fails.
  SimulationConfig c = traffic_config(14.0, 30.0, 1);
  c.traffic.launches = {planned(0.0, 400.0, 8.0, 0, 0.0), planned(0.0, 400.0, 0.0, 1, 90.0)};
  c.traffic.disposal.success_probability = 0.0;
  c.progress_every_steps = 2880;  // daily
  Simulation sim(c, {}, std::make_unique<SymplecticPropagator>(c.force_model, c.start_epoch, c.integrator));
  struct DailySink : LifecycleSink {
    Simulation* sim = nullptr;
    std::vector<std::pair<double, double>> km;  // (active, passive) at the end of each day
    void on_progress(std::uint64_t seq, const Progress& p) override {
      RecordingSink::on_progress(seq, p);
      km.emplace_back(altitude_km(sim->population(), kFirstLaunchId),
                      altitude_km(sim->population(), kFirstLaunchId + 1));
    }
  } sink;
  sink.sim = &sim;
  RunControl control;
  sim.run(sink, control);
  ASSERT_EQ(sink.km.size(), 14u);
  for (std::size_t d = 0; d < 8; ++d)
    std::printf("day %zu: active %.1f km, passive %.1f km\n", d + 1, sink.km[d].first, sink.km[d].second);
  // While active (days 1..7): within 15 km of 400 km (J2's short-period swing), the twin well below.
  for (std::size_t d = 0; d < 7; ++d) EXPECT_NEAR(sink.km[d].first, 400.0, 15.0) << d;
  EXPECT_LT(sink.km[6].second, 400.0 - 30.0);
  // Its life ends at day 8 (end of life, failed disposal), and it decays.
  ASSERT_EQ(sink.lifecycle.size(), 4u);
  EXPECT_EQ(sink.lifecycle[2].kind, LifecycleEventKind::kEndOfLife);
  EXPECT_EQ(sink.lifecycle[2].time_s, 8.0 * kDay_s);
  EXPECT_EQ(sink.lifecycle[3].kind, LifecycleEventKind::kDisposalFailed);
  EXPECT_LT(sink.km[13].first, sink.km[7].first - 20.0);
  EXPECT_EQ(sim.population().status[*sim.population().index_of(kFirstLaunchId)], ObjectStatus::kPassive);
}

TEST(TrafficLoop, ASuccessfulDisposalMovesItToItsDisposalOrbit) {
  SimulationConfig c = traffic_config(1.0, 30.0, 1);
  c.traffic.launches = {planned(0.0, 800.0, 0.5, 0, 0.0)};
  c.traffic.disposal.success_probability = 1.0;
  c.traffic.disposal.target_lifetime_years = 1.0;
  const auto out = run(c);
  ASSERT_EQ(out->sink.lifecycle.size(), 3u);
  const LifecycleReport& d = out->sink.lifecycle[2];
  EXPECT_EQ(d.kind, LifecycleEventKind::kDisposal);
  EXPECT_LT(d.altitude_m, 700e3);  // a year's life for 0.35 m^2/kg is well below 800 km
  EXPECT_NEAR(altitude_km(out->population, kFirstLaunchId), d.altitude_m / 1e3, 15.0);
  c.traffic.disposal.deorbit = true;
  const auto gone = run(c);
  EXPECT_EQ(gone->sink.lifecycle.back().kind, LifecycleEventKind::kDeorbit);
  EXPECT_TRUE(gone->population.empty());
}

// The population's own active payloads (a catalog's) keep station for a drawn remaining lifetime, then
// retire as launched ones do; passive ones and actives of other types are left alone.
TEST(TrafficLoop, TheCatalogsActivePayloadsRetireWithinTheirDrawnLifetimes) {
  SimulationConfig c = traffic_config(4.0, 60.0, 1);
  c.traffic.catalog_active_lifetime_years = 0.01;  // 3.65 days at most
  c.traffic.disposal.success_probability = 0.0;
  Population p;
  for (ObjectId id : {11, 12, 13}) {
    ObjectRecord o;
    o.id = id;
    Eigen::Vector3d r, v;
    OrbitElements el = elements_from_altitudes(600e3, 600e3, 0.9);
    el.raan_rad = 0.5 * static_cast<double>(id);
    state_from_elements(el, r, v);
    o.position_m = r;
    o.velocity_m_s = v;
    o.radius_m = 1.0;
    o.mass_kg = 100.0;
    o.drag_area_to_mass_m2_kg = 0.02;
    o.status = id == 13 ? ObjectStatus::kPassive : ObjectStatus::kActive;
    o.type = id == 12 ? ObjectType::kRocketBody : ObjectType::kPayload;
    p.add(o);
  }
  const auto out = run(c, p);
  ASSERT_EQ(out->sink.lifecycle.size(), 2u);  // object 11 only: end of life, failed disposal
  EXPECT_EQ(out->sink.lifecycle[0].kind, LifecycleEventKind::kEndOfLife);
  EXPECT_EQ(out->sink.lifecycle[0].first_id, 11u);
  EXPECT_LE(out->sink.lifecycle[0].time_s, 0.01 * 365.25 * kDay_s + 60.0);
  const std::size_t i = *out->population.index_of(11);
  EXPECT_EQ(out->population.status[i], ObjectStatus::kPassive);
  EXPECT_EQ(out->population.drag_area_to_mass_m2_kg[i], 0.02);  // its own drag back
  EXPECT_EQ(out->population.status[*out->population.index_of(12)], ObjectStatus::kActive);
}

TEST(TrafficLoop, ThreadsAndAResumeGiveTheSameBits) {
  auto config = [](int threads) {
    SimulationConfig c = traffic_config(2.0, 30.0, threads);
    for (int k = 0; k < 40; ++k)
      c.traffic.launches.push_back(planned(600.0 * k, 500.0 + 5.0 * k, k % 3 == 0 ? 0.0 : 0.2 + 0.02 * k,
                                           static_cast<std::size_t>(k / 4), 9.0 * k));
    c.traffic.disposal.success_probability = 0.5;
    c.conjunctions_enabled = true;
    c.conjunctions.screening_distance_m = 50e3;
    return c;
  };
  const auto one = run(config(1), test_population(200));
  ASSERT_GT(one->sink.lifecycle.size(), 40u);
  const auto two = run(config(2), test_population(200));
  EXPECT_EQ(two->summary.events_digest, one->summary.events_digest);
  EXPECT_EQ(two->summary.state_digest, one->summary.state_digest);
  // Stopped at step 1,000 (launches behind and ahead, lives running), resumed on 2 threads.
  struct Stop : LifecycleSink {
    RunControl* control = nullptr;
    void on_progress(std::uint64_t seq, const Progress& p) override {
      RecordingSink::on_progress(seq, p);
      if (p.step >= 1000) control->stop_after_checkpoint = true;
    }
  } first;
  RunControl control;
  first.control = &control;
  const SimulationConfig c1 = config(1);
  Simulation sim(c1, test_population(200),
                 std::make_unique<SymplecticPropagator>(c1.force_model, c1.start_epoch, c1.integrator));
  ASSERT_TRUE(sim.run(first, control).stopped_at_checkpoint);
  const SimulationConfig c2 = config(2);
  auto resumed = Simulation::resume(
      c2, first.checkpoints.at(0).bytes,
      std::make_unique<SymplecticPropagator>(c2.force_model, c2.start_epoch, c2.integrator));
  LifecycleSink second;
  RunControl control2;
  const RunSummary summary = resumed->run(second, control2);
  EXPECT_EQ(summary.events_digest, one->summary.events_digest);
  EXPECT_EQ(summary.state_digest, one->summary.state_digest);
}

}  // namespace
}  // namespace kessler
