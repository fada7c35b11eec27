// The main loop with stand-in parts: thread-count independence, checkpoint/resume bit for bit, corrupt
// checkpoints, run control.
#include "core/simulation/simulation.hpp"

#include <gtest/gtest.h>

#include <random>
#include <thread>

#include "core/integration/symplectic_propagator.hpp"
#include "core/simulation/checkpoint.hpp"
#include "core/simulation/sha256.hpp"
#include "core/simulation/steps_in_flight.hpp"
#include "tests/simulation/test_doubles.hpp"

namespace kessler {
namespace {

using namespace kessler::testing;

constexpr int kObjects = 400;

struct Outcome {
  RecordingSink sink;
  RunSummary summary;
  Population final_population;
};

std::unique_ptr<Outcome> run_fresh(SimulationConfig config, RunControl* control = nullptr) {
  auto out = std::make_unique<Outcome>();
  Simulation sim(config, test_population(kObjects), test_parts());
  RunControl own;
  out->summary = sim.run(out->sink, control ? *control : own);
  out->final_population = sim.population();
  return out;
}

void expect_same_events(const std::vector<RecordedEvent>& a, const std::vector<RecordedEvent>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i)
    ASSERT_TRUE(same_bits(a[i], b[i])) << "event " << i << " differs";
}

void expect_same_states(const Population& a, const Population& b) {
  ASSERT_EQ(a.id, b.id);
  EXPECT_EQ(a.state.x, b.state.x);
  EXPECT_EQ(a.state.y, b.state.y);
  EXPECT_EQ(a.state.z, b.state.z);
  EXPECT_EQ(a.state.vx, b.state.vx);
  EXPECT_EQ(a.state.vy, b.state.vy);
  EXPECT_EQ(a.state.vz, b.state.vz);
}

TEST(Simulation, OneTwoAndFourThreadsGiveTheSameBits) {
  auto one = run_fresh(test_config(240, 1));
  // The scenario is meant to exercise every event kind; otherwise the comparison below is hollow.
  ASSERT_GT(one->summary.conjunctions + one->summary.evasions, 5u);
  ASSERT_GT(one->summary.burn_ups, 0u);
  EXPECT_EQ(one->summary.objects_final, kObjects - one->summary.burn_ups);
  EXPECT_EQ(one->summary.steps, 240);
  ASSERT_TRUE(one->sink.finished.has_value());
  EXPECT_EQ(one->sink.finished->events_digest, one->summary.events_digest);
  EXPECT_EQ(one->summary.events_digest.size(), 64u);
  for (int threads : {2, 4}) {
    auto many = run_fresh(test_config(240, threads));
    expect_same_events(one->sink.events, many->sink.events);
    expect_same_states(one->final_population, many->final_population);
    EXPECT_EQ(many->summary.events_digest, one->summary.events_digest) << threads << " threads";
    EXPECT_EQ(many->summary.state_digest, one->summary.state_digest) << threads << " threads";
  }
}

// Steps in flight (steps_in_flight.hpp): scanned side by side, each by a scanner of its own, the steps give
// the events and states of one step at a time, bit for bit. Batches end at burn-ups (this run has
// some), at checkpoint steps, and hold more steps than threads where asked.
TEST(Simulation, StepsInFlightGiveTheBitsOfOneStepAtATime) {
  auto config = test_config(240, 2);
  config.scan_steps_at_once = 1;
  auto reference = run_fresh(config);
  ASSERT_GT(reference->summary.burn_ups, 0u);
  ASSERT_GT(reference->summary.conjunctions + reference->summary.evasions, 5u);
  struct Variant {
    int threads, at_once;
    std::int64_t checkpoint_every;
  };
  for (const Variant v : {Variant{2, 0, 0}, Variant{3, 0, 7}, Variant{2, 5, 0}, Variant{4, 3, 10}}) {
    auto c = config;
    c.threads = v.threads;
    c.scan_steps_at_once = v.at_once;
    c.checkpoint_every_steps = v.checkpoint_every;
    auto run = run_fresh(c);
    SCOPED_TRACE(std::to_string(v.threads) + " threads, " + std::to_string(v.at_once) + " at once");
    expect_same_events(reference->sink.events, run->sink.events);
    expect_same_states(reference->final_population, run->final_population);
    EXPECT_EQ(run->summary.events_digest, reference->summary.events_digest);
    for (const Checkpoint& k : run->sink.checkpoints) EXPECT_EQ(k.step % v.checkpoint_every, 0);
    if (v.checkpoint_every > 0)
      EXPECT_EQ(run->sink.checkpoints.size(), static_cast<std::size_t>(239 / v.checkpoint_every));
  }
}

// The same with the project's parts: the Yoshida-family propagator (its end-state copies) and the grid
// detector, whose steps in flight each build a grid of their own.
TEST(Simulation, ProjectPartsInFlightGiveTheBitsOfOneStepAtATime) {
  auto config = test_config(120, 1);
  config.conjunctions.screening_distance_m = 20e3;
  auto run_with = [&](int threads, int at_once) {
    auto c = config;
    c.threads = threads;
    c.scan_steps_at_once = at_once;
    auto out = std::make_unique<Outcome>();
    Simulation sim(c, test_population(kObjects),
                   std::make_unique<SymplecticPropagator>(c.force_model, c.start_epoch, c.integrator));
    RunControl control;
    out->summary = sim.run(out->sink, control);
    out->final_population = sim.population();
    return out;
  };
  auto one = run_with(1, 0);
  ASSERT_GT(one->summary.conjunctions + one->summary.evasions, 5u);
  ASSERT_GT(one->summary.burn_ups, 0u);
  for (auto [threads, at_once] : {std::pair{2, 0}, std::pair{3, 0}, std::pair{2, 4}}) {
    auto many = run_with(threads, at_once);
    SCOPED_TRACE(std::to_string(threads) + " threads, " + std::to_string(at_once) + " at once");
    expect_same_events(one->sink.events, many->sink.events);
    expect_same_states(one->final_population, many->final_population);
  }
}

// One step per thread for small populations whose extra memory fits the budget, else one at a time.
TEST(Simulation, StepsInFlightOnlyWhereTheyPay) {
  EXPECT_EQ(steps_in_flight_for(20000, 1), 1u);
  EXPECT_EQ(steps_in_flight_for(20000, 2), 2u);
  EXPECT_EQ(steps_in_flight_for(20000, 16), 16u);
  EXPECT_EQ(steps_in_flight_for(kFlightMaxObjects, 2), 2u);
  EXPECT_EQ(steps_in_flight_for(kFlightMaxObjects + 1, 2), 1u);  // larger steps: the team scan
  EXPECT_EQ(steps_in_flight_for(320000, 16), 1u);
  EXPECT_EQ(steps_in_flight_for(20000, 64), 1u);  // 63 more grids: ~500 MB
  for (std::size_t threads : {2u, 4u, 16u, 64u, 256u})
    for (std::size_t objects : {1000u, 10000u, 30000u, 400000u}) {
      const std::size_t at_once = steps_in_flight_for(objects, threads);
      EXPECT_TRUE(at_once == 1 || at_once == threads);
      EXPECT_LE((at_once - 1) * objects * kFlightBytesPerObjectPerStep, kFlightMemoryBudgetBytes);
    }
}

TEST(Simulation, SequenceNumbersAreGaplessAndOrderedWithinASTep) {
  auto run = run_fresh(test_config(120, 2));
  const auto& ev = run->sink.events;
  ASSERT_FALSE(ev.empty());
  for (std::size_t i = 0; i < ev.size(); ++i) EXPECT_EQ(ev[i].seq, i + 1);
  // Within a step: encounters in canonical order, then burn-ups by id, then progress.
  for (std::size_t i = 1; i < ev.size(); ++i) {
    if (ev[i - 1].type == 2) continue;
    EXPECT_LE(ev[i - 1].type, ev[i].type == 2 ? 2 : ev[i].type) << "event " << i;
    if (ev[i - 1].type == 0 && ev[i].type == 0 &&
        std::floor(ev[i - 1].encounter.tca_s / 10) == std::floor(ev[i].encounter.tca_s / 10)) {
      EXPECT_FALSE(canonical_less(ev[i].encounter, ev[i - 1].encounter));
    }
    if (ev[i - 1].type == 1 && ev[i].type == 1) {
      EXPECT_LT(ev[i - 1].burn_up.id, ev[i].burn_up.id);
    }
  }
  EXPECT_EQ(run->summary.events, run->summary.conjunctions + run->summary.evasions + run->summary.burn_ups);
}

TEST(Simulation, ResumedFromItsLastCheckpointMatchesAnUninterruptedRun) {
  auto config = test_config(240, 2);
  config.checkpoint_every_steps = 17;
  config.progress_every_steps = 1;
  auto whole = run_fresh(config);
  ASSERT_FALSE(whole->sink.checkpoints.empty());

  std::mt19937 rng(20260101);
  for (int trial = 0; trial < 3; ++trial) {
    const std::int64_t stop_step = std::uniform_int_distribution<std::int64_t>(18, 230)(rng);
    // First session: cancelled ("killed") right after the progress of stop_step.
    struct StoppingSink : RecordingSink {
      std::int64_t stop_step = 0;
      RunControl* control = nullptr;
      void on_progress(std::uint64_t seq, const Progress& p) override {
        RecordingSink::on_progress(seq, p);
        if (p.step == stop_step) control->cancel = true;
      }
    } first;
    RunControl control;
    first.stop_step = stop_step;
    first.control = &control;
    {
      Simulation sim(config, test_population(kObjects), test_parts());
      auto s = sim.run(first, control);
      ASSERT_TRUE(s.cancelled);
      // Read at the end of the batch: two steps in flight on two threads.
      ASSERT_GE(sim.step(), stop_step);
      ASSERT_LE(sim.step(), stop_step + 1);
    }
    ASSERT_FALSE(first.checkpoints.empty());
    const Checkpoint& last = first.checkpoints.back();
    EXPECT_EQ(last.step % 17, 0);

    // Second session from the checkpoint, different thread count.
    auto config4 = config;
    config4.threads = 4;
    auto resumed = Simulation::resume(config4, last.bytes, test_parts());
    EXPECT_EQ(resumed->step(), last.step);
    RecordingSink second;
    RunControl control2;
    auto summary = resumed->run(second, control2);
    ASSERT_FALSE(second.events.empty());
    EXPECT_EQ(second.events.front().seq, last.last_seq + 1) << "events lost or repeated at the resume point";

    // What a consumer keeps: the first session's events up to the checkpoint, then the second's.
    std::vector<RecordedEvent> stitched;
    for (const auto& e : first.events)
      if (e.seq <= last.last_seq) stitched.push_back(e);
    stitched.insert(stitched.end(), second.events.begin(), second.events.end());
    expect_same_events(whole->sink.events, stitched);
    expect_same_states(whole->final_population, resumed->population());
    EXPECT_EQ(summary.events_digest, whole->summary.events_digest);
    EXPECT_EQ(summary.state_digest, whole->summary.state_digest);
    EXPECT_EQ(summary.events, whole->summary.events);
    EXPECT_EQ(summary.burn_ups, whole->summary.burn_ups);
  }
}

TEST(Simulation, ClosestEncounterTableSurvivesACheckpoint) {
  auto config = test_config(200, 1);
  Simulation whole(config, test_population(kObjects), test_parts());
  RecordingSink sink;
  RunControl control;
  whole.run(sink, control);
  ASSERT_FALSE(whole.closest_encounters().empty());

  Simulation part(config, test_population(kObjects), test_parts());
  struct Stop : RecordingSink {
    RunControl* c;
    void on_progress(std::uint64_t s, const Progress& p) override {
      RecordingSink::on_progress(s, p);
      if (p.step == 110) c->stop_after_checkpoint = true;
    }
  } stop;
  RunControl c2;
  stop.c = &c2;
  auto s = part.run(stop, c2);
  EXPECT_TRUE(s.stopped_at_checkpoint);
  EXPECT_FALSE(stop.finished.has_value()) << "a stop at a checkpoint is not a finish";
  ASSERT_EQ(stop.checkpoints.size(), 1u);
  EXPECT_EQ(stop.checkpoints[0].step, 110);
  auto resumed = Simulation::resume(config, stop.checkpoints[0].bytes, test_parts());
  RecordingSink rest;
  RunControl c3;
  resumed->run(rest, c3);
  auto a = whole.closest_encounters(), b = resumed->closest_encounters();
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].id1, b[i].id1);
    EXPECT_EQ(a[i].id2, b[i].id2);
    EXPECT_EQ(a[i].miss_distance_m, b[i].miss_distance_m);
    EXPECT_EQ(a[i].tca_s, b[i].tca_s);
  }
}

TEST(Simulation, CorruptOrForeignCheckpointsAreRefused) {
  auto config = test_config(60, 1);
  Simulation sim(config, test_population(50), test_parts());
  const std::string good = sim.checkpoint();
  EXPECT_NO_THROW(Simulation::resume(config, good, test_parts()));

  auto message = [&](const std::string& bytes, const SimulationConfig& c) {
    try {
      Simulation::resume(c, bytes, test_parts());
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  std::string flipped = good;
  flipped[flipped.size() / 2] ^= 0x10;
  EXPECT_EQ(message(flipped, config), "checkpoint: checksum mismatch (corrupt bytes)");
  EXPECT_EQ(message(good.substr(0, good.size() - 5), config),
            "checkpoint: truncated or padded (payload size does not match)");
  EXPECT_EQ(message("hello", config), "checkpoint: not a kessler checkpoint (bad header)");
  std::string future = good;
  future[8] = 9;
  EXPECT_EQ(message(future, config),
            "checkpoint: format version 9 is not supported (this build reads 1 to 4)");
  auto other = config;
  other.dt_s = 5.0;
  EXPECT_NE(message(good, other).find("different scenario"), std::string::npos);
}

TEST(Simulation, CheckpointRoundTripKeepsEveryField) {
  CheckpointState s;
  s.config_key = "abc";
  s.step = 5;
  s.total_steps = 9;
  s.next_seq = 42;
  s.seed = 77;
  s.burn_ups = 3;
  s.events_digest_state = std::string(Sha256::kStateBytes, 'x');
  s.population = test_population(10);
  s.population.state.x[3] = -0.0;
  Encounter e;
  e.id1 = 1;
  e.id2 = 2;
  e.tca_s = 1.0 / 3.0;
  e.kind = EncounterKind::kCollision;
  e.r1_m = {1, 2, 3};
  e.v1_m_s = {4, 5, 6};
  e.r2_m = {7, 8, 9};
  e.v2_m_s = {10, 11, 12};
  s.closest_per_pair.push_back(e);
  s.breakups.next_fragment_id = kFirstFragmentId + 123;
  s.breakups.next_breakup_id = 4;
  s.breakups.separating = {{2, 1234.5}, {3, 1e9 / 7.0}};
  s.population.type[1] = ObjectType::kRocketBody;
  s.population.type[2] = ObjectType::kDebris;
  s.population.separation_group[5] = 3;
  CheckpointState back = decode_checkpoint(encode_checkpoint(s));
  EXPECT_EQ(back.breakups.next_fragment_id, kFirstFragmentId + 123);
  EXPECT_EQ(back.breakups.next_breakup_id, 4u);
  ASSERT_EQ(back.breakups.separating.size(), 2u);
  EXPECT_EQ(back.breakups.separating[1].group, 3u);
  EXPECT_EQ(back.breakups.separating[1].until_s, 1e9 / 7.0);
  EXPECT_EQ(back.population.type, s.population.type);
  EXPECT_EQ(back.population.separation_group, s.population.separation_group);
  EXPECT_EQ(back.step, 5);
  EXPECT_EQ(back.next_seq, 42u);
  EXPECT_EQ(back.seed, 77u);
  EXPECT_EQ(back.burn_ups, 3u);
  EXPECT_EQ(back.population.name, s.population.name);
  EXPECT_EQ(back.population.radius_m, s.population.radius_m);
  EXPECT_EQ(back.population.status, s.population.status);
  EXPECT_TRUE(std::signbit(back.population.state.x[3]));
  ASSERT_EQ(back.closest_per_pair.size(), 1u);
  EXPECT_EQ(back.closest_per_pair[0].tca_s, 1.0 / 3.0);
  EXPECT_EQ(back.closest_per_pair[0].kind, EncounterKind::kCollision);
  EXPECT_EQ(back.closest_per_pair[0].v2_m_s, Eigen::Vector3d(10, 11, 12));
}

TEST(Simulation, CancelTakesEffectWithinOneStep) {
  struct CancelAt : RecordingSink {
    RunControl* c;
    void on_progress(std::uint64_t s, const Progress& p) override {
      RecordingSink::on_progress(s, p);
      if (p.step == 30) c->cancel = true;
    }
  } sink;
  RunControl control;
  sink.c = &control;
  auto config = test_config(100, 1);
  Simulation sim(config, test_population(60), test_parts());
  auto s = sim.run(sink, control);
  EXPECT_TRUE(s.cancelled);
  EXPECT_EQ(s.steps, 30);
  ASSERT_TRUE(sink.finished.has_value());
  EXPECT_TRUE(sink.finished->cancelled);
}

TEST(Simulation, PauseHoldsTheLoopAndCheckpointNowWritesOne) {
  struct PauseAt : RecordingSink {
    RunControl* c;
    void on_progress(std::uint64_t s, const Progress& p) override {
      RecordingSink::on_progress(s, p);
      if (p.step == 20) c->pause = true;
    }
  } sink;
  RunControl control;
  sink.c = &control;
  auto config = test_config(50, 1);
  Simulation sim(config, test_population(60), test_parts());
  std::thread host([&] {
    while (!control.pause) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    EXPECT_EQ(sim.step(), 20);  // held at the boundary
    control.checkpoint_now = true;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    control.pause = false;
  });
  auto s = sim.run(sink, control);
  host.join();
  EXPECT_EQ(s.steps, 50);
  ASSERT_EQ(sink.checkpoints.size(), 1u);
  EXPECT_EQ(sink.checkpoints[0].step, 20);
}

TEST(Simulation, FailuresReachTheSink) {
  struct Broken : Propagator {
    void step(Population&, double t, double) override {
      if (t > 50) throw std::runtime_error("integrator diverged");
    }
  };
  SimulationParts parts;
  parts.propagator = std::make_unique<Broken>();
  Simulation sim(test_config(20, 1), test_population(10), std::move(parts));
  RecordingSink sink;
  RunControl control;
  EXPECT_THROW(sim.run(sink, control), std::runtime_error);
  EXPECT_EQ(sink.failure, "integrator diverged");
  EXPECT_FALSE(sink.finished.has_value());
}

// A scanner that fails on a step scanned in flight (inside the batch's parallel region) fails the run
// the same way: the exception reaches the caller and the sink, nothing terminates.
TEST(Simulation, AScanFailingInFlightReachesTheSink) {
  struct Failing : EncounterScanner {
    void scan(const Population&, const StepEnds& step, std::vector<Encounter>&) override {
      if (step.t_start_s > 45) throw std::runtime_error("scan failed at " + std::to_string(step.t_start_s));
    }
    std::unique_ptr<EncounterScanner> another() const override { return std::make_unique<Failing>(); }
  };
  SimulationParts parts;
  parts.propagator = std::make_unique<KeplerRk4Propagator>();
  parts.scanner = std::make_unique<Failing>();
  parts.burn_up = false;
  auto config = test_config(20, 2);
  config.scan_steps_at_once = 4;  // steps 4-7 (t = 40 ... 70 s) in one batch: t = 50 fails
  Simulation sim(config, test_population(10), std::move(parts));
  RecordingSink sink;
  RunControl control;
  EXPECT_THROW(sim.run(sink, control), std::runtime_error);
  EXPECT_EQ(sink.failure.substr(0, 17), "scan failed at 50");
  EXPECT_FALSE(sink.finished.has_value());
}

TEST(Simulation, StepCount) {
  SimulationConfig c;
  c.dt_s = 10;
  c.duration_s = 86400;
  EXPECT_EQ(total_steps_of(c), 8640);
  c.duration_s = 15;
  EXPECT_EQ(total_steps_of(c), 1);
  c.dt_s = 0.1;
  c.duration_s = 0.3;
  EXPECT_EQ(total_steps_of(c), 3);
}

}  // namespace
}  // namespace kessler
