// Scheduled breakups in the main loop (core/simulation/breakups.hpp) with the stand-in parts:
// the model's fragments with the expected ids, the same bits on any thread count and across a checkpoint
// between or at breakups, version 1 checkpoints still read, and nothing changed while disabled.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstring>

#include "core/breakup/fragment_cloud.hpp"
#include "core/simulation/checkpoint.hpp"
#include "core/simulation/sha256.hpp"
#include "core/simulation/simulation.hpp"
#include "tests/simulation/test_doubles.hpp"

namespace kessler {
namespace {

using namespace kessler::testing;

constexpr int kObjects = 400;
constexpr ObjectId kExploding = 1021, kStriking = 1030, kStruck = 1042;  // not among the decaying ones

// An explosion at the end of step 50 (given as a step) and a collision at the end of step 80 (given as
// 795 s: a breakup inside a step happens at its end).
SimulationConfig breakup_config(std::int64_t steps, int threads) {
  SimulationConfig c = test_config(steps, threads);
  c.progress_every_steps = 1;
  c.breakups.enabled = true;
  ScheduledBreakup explosion;
  explosion.step = 50;
  explosion.kind = BreakupKind::kExplosion;
  explosion.object_ids = {kExploding};
  ScheduledBreakup collision;
  collision.epoch_offset_s = 795.0;
  collision.kind = BreakupKind::kCollision;
  collision.object_ids = {kStriking, kStruck};
  collision.masses_kg = {80.0, 300.0};
  c.breakups.scheduled = {explosion, collision};
  return c;
}

struct BreakupSink : RecordingSink {
  std::vector<std::pair<std::uint64_t, BreakupReport>> breakups;
  void on_breakup(std::uint64_t seq, const BreakupReport& b) override { breakups.push_back({seq, b}); }
};

struct Run {
  BreakupSink sink;
  RunSummary summary;
  Population population;
};

std::unique_ptr<Run> run_fresh(const SimulationConfig& config) {
  auto out = std::make_unique<Run>();
  Simulation sim(config, test_population(kObjects), test_parts());
  RunControl control;
  out->summary = sim.run(out->sink, control);
  out->population = sim.population();
  return out;
}

TEST(ScheduledBreakups, AnExplosionAddsTheModelsFragmentsWithTheirIds) {
  // The parent's state at the end of step 50 from a run without breakups (identical up to there).
  SimulationConfig plain = test_config(50, 1);
  Simulation before(plain, test_population(kObjects), test_parts());
  RecordingSink ignored;
  RunControl control;
  before.run(ignored, control);
  const Population& p = before.population();
  const std::size_t i = *p.index_of(kExploding);
  BreakupEvent e;
  e.kind = BreakupKind::kExplosion;
  e.seed = plain.seed;
  e.event_id = 1;  // the run's first breakup
  e.parents = {BreakupParent{kExploding,
                             p.mass_kg[i],
                             2.0 * p.radius_m[i],
                             BreakupObjectClass::kRocketBody,
                             {p.state.x[i], p.state.y[i], p.state.z[i]},
                             {p.state.vx[i], p.state.vy[i], p.state.vz[i]}}};
  const FragmentCloud cloud = generate_fragments(e);
  ASSERT_GT(cloud.size(), 100u);

  SimulationConfig config = breakup_config(60, 1);
  config.breakups.scheduled.resize(1);
  const auto run = run_fresh(config);
  ASSERT_EQ(run->sink.breakups.size(), 1u);
  const BreakupReport& r = run->sink.breakups[0].second;
  EXPECT_EQ(r.time_s, 500.0);
  EXPECT_EQ(r.parents, std::vector<ObjectId>{kExploding});
  EXPECT_TRUE(r.catastrophic);
  EXPECT_EQ(r.fragment_count, cloud.size());
  EXPECT_EQ(r.fragment_mass_kg, cloud.fragment_mass_kg);
  EXPECT_EQ(r.first_id, kFirstFragmentId);
  EXPECT_EQ(r.last_id, kFirstFragmentId + cloud.size() - 1);
  const Population& q = run->population;
  EXPECT_FALSE(q.index_of(kExploding).has_value());
  EXPECT_EQ(q.size(), kObjects - run->summary.burn_ups - 1 + cloud.size());
  for (std::size_t k = 0; k < cloud.size(); ++k) {
    const auto at = q.index_of(kFirstFragmentId + k);
    ASSERT_TRUE(at.has_value()) << k;
    EXPECT_EQ(q.mass_kg[*at], cloud.mass_kg[k]);
    EXPECT_EQ(q.radius_m[*at], cloud.characteristic_length_m[k] / 2);
    EXPECT_DOUBLE_EQ(q.drag_area_to_mass_m2_kg[*at], 2.2 * cloud.area_to_mass_m2_kg[k]);
    EXPECT_EQ(q.status[*at], ObjectStatus::kPassive);
  }
  // Within the step: progress after the breakup, which it counts.
  const auto& ev = run->sink.events;
  const auto progress_50 = std::find_if(
      ev.begin(), ev.end(), [](const RecordedEvent& x) { return x.type == 2 && x.progress.step == 50; });
  ASSERT_NE(progress_50, ev.end());
  EXPECT_EQ(progress_50->seq, run->sink.breakups[0].first + 1);
  EXPECT_EQ(progress_50->progress.objects_alive, kObjects - run->summary.burn_ups - 1 + cloud.size());
}

TEST(ScheduledBreakups, IdsRunOnAcrossEventsAndThreadCountsGiveTheSameBits) {
  const auto one = run_fresh(breakup_config(120, 1));
  ASSERT_EQ(one->sink.breakups.size(), 2u);
  const BreakupReport &a = one->sink.breakups[0].second, &b = one->sink.breakups[1].second;
  EXPECT_EQ(b.time_s, 800.0);
  EXPECT_EQ(b.first_id, a.last_id + 1);
  EXPECT_GT(b.fragment_count, 0u);
  std::printf("explosion: %llu fragments (%.1f kg); collision: %s, %.0f J/g, %llu fragments (%.1f kg)\n",
              static_cast<unsigned long long>(a.fragment_count), a.fragment_mass_kg,
              b.catastrophic ? "catastrophic" : "non-catastrophic", b.specific_energy_j_per_g,
              static_cast<unsigned long long>(b.fragment_count), b.fragment_mass_kg);
  EXPECT_GT(one->summary.conjunctions + one->summary.evasions, 0u);
  for (int threads : {2, 4}) {
    const auto many = run_fresh(breakup_config(120, threads));
    SCOPED_TRACE(std::to_string(threads) + " threads");
    EXPECT_EQ(many->summary.events_digest, one->summary.events_digest);
    EXPECT_EQ(many->summary.state_digest, one->summary.state_digest);
    EXPECT_EQ(many->population.id, one->population.id);
  }
}

// Stopped at a checkpoint at step 65 (between the breakups) or 80 (at the collision), resumed on
// another thread count: the events and states of a straight run.
TEST(ScheduledBreakups, ACheckpointBetweenOrAtBreakupsResumesBitForBit) {
  const auto whole = run_fresh(breakup_config(120, 1));
  for (std::int64_t stop_step : {65, 80}) {
    struct Stop : BreakupSink {
      RunControl* control = nullptr;
      std::int64_t at = 0;
      void on_progress(std::uint64_t seq, const Progress& p) override {
        RecordingSink::on_progress(seq, p);
        if (p.step == at) control->stop_after_checkpoint = true;
      }
    } first;
    RunControl control;
    first.control = &control;
    first.at = stop_step;
    Simulation sim(breakup_config(120, 1), test_population(kObjects), test_parts());
    ASSERT_TRUE(sim.run(first, control).stopped_at_checkpoint);
    ASSERT_EQ(first.checkpoints.size(), 1u);
    ASSERT_EQ(first.checkpoints[0].step, stop_step);
    auto resumed = Simulation::resume(breakup_config(120, 2), first.checkpoints[0].bytes, test_parts());
    BreakupSink second;
    RunControl control2;
    const RunSummary summary = resumed->run(second, control2);
    SCOPED_TRACE("stopped at step " + std::to_string(stop_step));
    EXPECT_EQ(first.breakups.size() + second.breakups.size(), 2u);
    EXPECT_EQ(summary.events_digest, whole->summary.events_digest);
    EXPECT_EQ(summary.state_digest, whole->summary.state_digest);
    EXPECT_EQ(summary.events, whole->summary.events);
  }
}

// A version 1 checkpoint (no fragment counter) is still read: its run has made no fragments.
TEST(ScheduledBreakups, VersionOneCheckpointsAreRead) {
  CheckpointState s;
  s.config_key = "abc";
  s.step = 1;
  s.total_steps = 2;
  s.population = test_population(3);
  std::string bytes = encode_checkpoint(s);
  // Less version 3's types and groups (3 objects), breakup counter and separating list, version 4's
  // traffic state (counter, empty list), and the counter.
  const std::size_t payload = bytes.size() - 8 - 12 - 32 - (3 * 1 + 3 * 8 + 8 + 8) - (8 + 8) - 8;
  std::string v1 = bytes.substr(0, 8);
  for (std::uint32_t k = 0, v = 1; k < 4; ++k) v1.push_back(static_cast<char>(v >> (8 * k)));
  for (std::uint64_t k = 0; k < 8; ++k) v1.push_back(static_cast<char>(payload >> (8 * k)));
  v1.append(bytes, 20, payload);
  Sha256 sum;
  sum.update(bytes.data() + 20, payload);
  const auto digest = sum.digest();
  v1.append(reinterpret_cast<const char*>(digest.data()), digest.size());
  const CheckpointState back = decode_checkpoint(v1);
  EXPECT_EQ(back.breakups.next_fragment_id, kFirstFragmentId);
  EXPECT_EQ(back.population.id, s.population.id);
}

// Disabled, a schedule changes nothing: the events and states of a run without one.
TEST(ScheduledBreakups, DisabledChangesNothing) {
  SimulationConfig off = breakup_config(120, 2);
  off.breakups.enabled = false;
  SimulationConfig plain = test_config(120, 2);
  plain.progress_every_steps = 1;
  const auto a = run_fresh(off), b = run_fresh(plain);
  EXPECT_TRUE(a->sink.breakups.empty());
  EXPECT_EQ(a->summary.events_digest, b->summary.events_digest);
  EXPECT_EQ(a->summary.state_digest, b->summary.state_digest);
}

}  // namespace
}  // namespace kessler
