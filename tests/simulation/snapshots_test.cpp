// Population snapshots in the loop: osculating elements against Vallado's worked example, snapshots at
// the start, every interval and the last step, matching the population there; no change to events,
// digests or checkpoints; a resumed run hands over the snapshots after its checkpoint.
#include "core/simulation/snapshots.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "core/simulation/simulation.hpp"
#include "core/traffic/orbit_elements.hpp"
#include "tests/simulation/test_doubles.hpp"

namespace kessler {
namespace {

using namespace kessler::testing;

constexpr double kDeg = std::numbers::pi / 180.0;

struct SnapshotSink : RecordingSink {
  std::vector<std::shared_ptr<const PopulationSnapshot>> snapshots;
  std::int64_t cancel_after_step = -1;
  RunControl* control = nullptr;
  void on_snapshot(const std::shared_ptr<const PopulationSnapshot>& s) override { snapshots.push_back(s); }
  void on_progress(std::uint64_t seq, const Progress& p) override {
    RecordingSink::on_progress(seq, p);
    if (p.step == cancel_after_step) control->cancel = true;
  }
};

// Vallado, Fundamentals of Astrodynamics and Applications (4th ed.), Example 2-5 (RV2COE):
// r = (6524.834, 6862.875, 6448.296) km, v = (4.901327, 5.533756, -1.976341) km/s give a = 36127.343 km,
// e = 0.832853, i = 87.870 deg, RAAN = 227.89 deg, argument of perigee = 53.38 deg, true anomaly 92.335 deg.
TEST(Snapshots, OsculatingElementsMatchValladosExample) {
  const OsculatingElements el =
      osculating_elements(6524.834e3, 6862.875e3, 6448.296e3, 4.901327e3, 5.533756e3, -1.976341e3);
  EXPECT_NEAR(el.semi_major_axis_m / 1e3, 36127.343, 0.5);
  EXPECT_NEAR(el.eccentricity, 0.832853, 1e-6);
  EXPECT_NEAR(el.inclination_rad / kDeg, 87.870, 1e-3);
  EXPECT_NEAR(el.raan_rad / kDeg, 227.89, 0.01);
  EXPECT_NEAR(el.argument_of_perigee_rad / kDeg, 53.38, 0.01);
  // The mean anomaly of a true anomaly of 92.335 deg (half-angle form of the eccentric anomaly).
  const double e = 0.832853, nu = 92.335 * kDeg;
  const double ea = 2.0 * std::atan(std::sqrt((1.0 - e) / (1.0 + e)) * std::tan(nu / 2.0));
  EXPECT_NEAR(el.mean_anomaly_rad, ea - e * std::sin(ea), 2e-5);
}

TEST(Snapshots, CircularAndEquatorialOrbitsHaveDefinedAngles) {
  OrbitElements in;
  in.semi_major_axis_m = 7000e3;
  in.inclination_rad = 0.0;
  in.mean_anomaly_rad = 1.0;
  Eigen::Vector3d r, v;
  state_from_elements(in, r, v);
  const OsculatingElements el = osculating_elements(r.x(), r.y(), r.z(), v.x(), v.y(), v.z());
  EXPECT_NEAR(el.semi_major_axis_m, 7000e3, 1e-3);
  EXPECT_NEAR(el.eccentricity, 0.0, 1e-12);
  EXPECT_EQ(el.raan_rad, 0.0);
  EXPECT_EQ(el.argument_of_perigee_rad, 0.0);
  EXPECT_NEAR(el.mean_anomaly_rad, 1.0, 1e-9);  // from the x axis
}

TEST(Snapshots, IntervalRule) {
  EXPECT_EQ(snapshot_interval_steps(0.0, 10.0, 1000), 0);
  EXPECT_EQ(snapshot_interval_steps(-1.0, 10.0, 1000), 20);  // about 50 per run
  EXPECT_EQ(snapshot_interval_steps(-1.0, 10.0, 7), 1);
  EXPECT_EQ(snapshot_interval_steps(864000.0, 10.0, 63115200), 86400);  // 10 days of 10 s steps
  EXPECT_EQ(snapshot_interval_steps(1.0, 10.0, 1000), 1);
}

TEST(Snapshots, TakenAtTheStartEveryIntervalAndTheLastStepWithoutChangingTheRun) {
  SimulationConfig plain = test_config(245, 2);
  plain.checkpoint_every_steps = 50;
  SimulationConfig with = plain;
  with.snapshot_every_steps = 40;
  SnapshotSink a, b;
  RunControl ca, cb;
  Simulation sa(plain, test_population(300), test_parts());
  Simulation sb(with, test_population(300), test_parts());
  const RunSummary ra = sa.run(a, ca), rb = sb.run(b, cb);
  EXPECT_EQ(ra.events_digest, rb.events_digest);
  EXPECT_EQ(ra.state_digest, rb.state_digest);
  ASSERT_EQ(a.checkpoints.size(), b.checkpoints.size());
  // The same checkpoints (their bytes differ only in the wall time they carry): a run with snapshots
  // resumes from one taken without them, to the same digests.
  for (std::size_t i = 0; i < a.checkpoints.size(); ++i) {
    EXPECT_EQ(a.checkpoints[i].step, b.checkpoints[i].step);
    EXPECT_EQ(a.checkpoints[i].last_seq, b.checkpoints[i].last_seq);
  }
  SnapshotSink c;
  RunControl cc;
  const RunSummary rc = Simulation::resume(with, a.checkpoints[1].bytes, test_parts())->run(c, cc);
  EXPECT_EQ(rc.events_digest, ra.events_digest);
  EXPECT_EQ(rc.state_digest, ra.state_digest);
  EXPECT_TRUE(a.snapshots.empty());
  std::vector<std::int64_t> steps;
  for (const auto& s : b.snapshots) steps.push_back(s->step);
  EXPECT_EQ(steps, (std::vector<std::int64_t>{0, 40, 80, 120, 160, 200, 240, 245}));
  // The last one is the final population, element by element.
  const PopulationSnapshot& last = *b.snapshots.back();
  const Population& p = sb.population();
  ASSERT_EQ(last.id, p.id);
  EXPECT_EQ(last.sim_time_s, 2450.0);
  for (std::size_t i = 0; i < p.size(); ++i) {
    const OsculatingElements el = osculating_elements(p.state.x[i], p.state.y[i], p.state.z[i], p.state.vx[i],
                                                      p.state.vy[i], p.state.vz[i]);
    EXPECT_EQ(last.semi_major_axis_m[i], static_cast<float>(el.semi_major_axis_m));
    EXPECT_EQ(last.inclination_rad[i], static_cast<float>(el.inclination_rad));
    EXPECT_EQ(last.radius_m[i], static_cast<float>(p.radius_m[i]));
    EXPECT_EQ(last.status[i], p.status[i]);
  }
  // Burn-ups (every 40th object decays) show as fewer objects in later snapshots.
  EXPECT_LT(last.size(), b.snapshots.front()->size());
}

TEST(Snapshots, AResumedRunHandsOverTheSnapshotsAfterItsCheckpoint) {
  SimulationConfig config = test_config(200, 2);
  config.checkpoint_every_steps = 30;
  config.snapshot_every_steps = 20;
  config.progress_every_steps = 1;
  SnapshotSink whole;
  RunControl cw;
  Simulation(config, test_population(200), test_parts()).run(whole, cw);

  SnapshotSink first;
  RunControl c1;
  first.cancel_after_step = 75;
  first.control = &c1;
  Simulation(config, test_population(200), test_parts()).run(first, c1);
  const Checkpoint& last = first.checkpoints.back();
  ASSERT_EQ(last.step, 60);
  SnapshotSink second;
  RunControl c2;
  Simulation::resume(config, last.bytes, test_parts())->run(second, c2);
  // Kept by step: the first session's up to the checkpoint, the second's after it.
  std::vector<std::shared_ptr<const PopulationSnapshot>> stitched;
  for (const auto& s : first.snapshots)
    if (s->step <= last.step) stitched.push_back(s);
  ASSERT_FALSE(second.snapshots.empty());
  EXPECT_EQ(second.snapshots.front()->step, 80);
  stitched.insert(stitched.end(), second.snapshots.begin(), second.snapshots.end());
  ASSERT_EQ(stitched.size(), whole.snapshots.size());
  for (std::size_t k = 0; k < stitched.size(); ++k) {
    EXPECT_EQ(stitched[k]->step, whole.snapshots[k]->step);
    EXPECT_EQ(stitched[k]->id, whole.snapshots[k]->id);
    EXPECT_EQ(stitched[k]->semi_major_axis_m, whole.snapshots[k]->semi_major_axis_m);
    EXPECT_EQ(stitched[k]->mean_anomaly_rad, whole.snapshots[k]->mean_anomaly_rad);
  }
}

}  // namespace
}  // namespace kessler
