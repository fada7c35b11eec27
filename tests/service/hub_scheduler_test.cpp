// The event hub (bounded window, behind detection, resumed runs), the event relay (order, contents,
// checkpoints after their events) and the scheduler (order, limit, cancel, shutdown) with a fake run
// in place of a simulation.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <thread>

#include "tests/service/temp_dir.hpp"

#include "server/event_hub.hpp"
#include "server/event_relay.hpp"
#include "server/scheduler.hpp"
#include "server/store.hpp"

namespace kessler::server {
namespace {

EventPtr event(std::uint64_t seq) {
  auto e = std::make_shared<v1::RunEvent>();
  e->set_seq(seq);
  return e;
}

// What the simulation hands the relay reaches hub and store in order, in wire form, with a
// checkpoint stored after the events before it; drain() leaves nothing behind.
TEST(EventRelay, HandsEventsAndCheckpointsToHubAndStoreInOrder) {
  TempDir dir;
  Store store(dir.path() + "/k.db");
  const std::int64_t id = store.create_run(v1::Scenario(), 0, 0.0);
  EventHub hub(0, 100000);
  EventRelay relay(id, hub, store, std::chrono::milliseconds(2));
  std::uint64_t seq = 0;
  for (int step = 0; step < 300; ++step) {
    Encounter e;
    e.id1 = 100 + step;
    e.id2 = 200 + step;
    e.tca_s = step * 10.0 + 1.5;
    e.miss_distance_m = 42.0 + step;
    e.kappa = 0.25;
    e.kind = EncounterKind::kEvasion;
    e.r1_m = Eigen::Vector3d(7e6, 1, 2);
    e.v1_m_s = Eigen::Vector3d(3, 7.5e3, 4);
    e.r2_m = Eigen::Vector3d(7e6 + 5, 6, 7);
    e.v2_m_s = Eigen::Vector3d(8, 9, 7.4e3);
    relay.on_encounter(++seq, e);
    if (step % 7 == 0) relay.on_burn_up(++seq, BurnUp{static_cast<ObjectId>(step), step * 10.0, 149e3});
    Progress p;
    p.step = step + 1;
    p.total_steps = 300;
    relay.on_progress(++seq, p);
    if (step == 150) relay.on_checkpoint(seq, step + 1, "checkpoint bytes");
    if (step % 50 == 0) std::this_thread::sleep_for(std::chrono::milliseconds(3));  // several batches
  }
  relay.drain();
  auto live = hub.read_after(0, 100000);
  ASSERT_EQ(live.events.size(), seq);
  for (std::uint64_t i = 0; i < seq; ++i) {
    EXPECT_EQ(live.events[i]->seq(), i + 1);
    EXPECT_EQ(live.events[i]->run_id(), id);
  }
  const v1::RunEvent& first = *live.events[0];
  ASSERT_TRUE(first.has_encounter());
  EXPECT_EQ(first.encounter().id1(), 100u);
  EXPECT_EQ(first.encounter().seq(), 1u);
  EXPECT_EQ(first.encounter().kind(), v1::ENCOUNTER_KIND_EVASION);
  EXPECT_DOUBLE_EQ(first.encounter().v2_m_s().z(), 7.4e3);
  ASSERT_TRUE(live.events[1]->has_burn_up());
  EXPECT_DOUBLE_EQ(live.events[1]->burn_up().altitude_m(), 149e3);
  ASSERT_TRUE(live.events[2]->has_progress());
  EXPECT_EQ(live.events[2]->progress().step(), 1);
  store.flush();
  EXPECT_EQ(store.max_seq(id), seq);
  auto stored = store.read_events(id, 0, 100000);
  ASSERT_EQ(stored.size(), seq);
  EXPECT_EQ(stored.back().SerializeAsString(), live.events.back()->SerializeAsString());
  auto checkpoint = store.latest_checkpoint(id);
  ASSERT_TRUE(checkpoint);
  EXPECT_EQ(checkpoint->step, 151);
  EXPECT_EQ(checkpoint->bytes, "checkpoint bytes");
}

// Within the store's checkpoint interval, later checkpoints are not even copied (the store would
// only hold them back to be replaced), except the one a stopping run takes last.
TEST(EventRelay, TakesCheckpointsAtMostOncePerIntervalUnlessTheRunStopsAfterIt) {
  TempDir dir;
  Store store(dir.path() + "/k.db");  // writes every checkpoint it is given
  const std::int64_t id = store.create_run(v1::Scenario(), 0, 0.0);
  EventHub hub;
  RunControl control;
  {
    EventRelay relay(id, hub, store, std::chrono::milliseconds(1), std::chrono::hours(1), &control);
    Progress p;
    relay.on_progress(1, p);
    relay.on_checkpoint(1, 10, "first");
    relay.on_progress(2, p);
    relay.on_checkpoint(2, 20, "second");  // within the hour: not taken
    relay.drain();
  }
  store.flush();
  EXPECT_EQ(store.latest_checkpoint(id)->bytes, "first");
  {
    EventRelay relay(id, hub, store, std::chrono::milliseconds(1), std::chrono::hours(1), &control);
    relay.on_checkpoint(2, 20, "resumable");
    control.stop_after_checkpoint = true;
    relay.on_checkpoint(3, 30, "last before stopping");
    relay.drain();
  }
  store.flush();
  EXPECT_EQ(store.latest_checkpoint(id)->bytes, "last before stopping");
}

TEST(EventHub, KeepsABoundedWindowAndTellsAReaderWhenItFellBehind) {
  EventHub hub(0, 4);
  for (std::uint64_t s = 1; s <= 10; ++s) hub.publish(event(s));
  EXPECT_EQ(hub.last_seq(), 10u);
  auto behind = hub.read_after(3, 100);
  EXPECT_TRUE(behind.behind);
  EXPECT_TRUE(behind.events.empty());
  auto live = hub.read_after(6, 100);  // 7..10 are in the window
  EXPECT_FALSE(live.behind);
  ASSERT_EQ(live.events.size(), 4u);
  EXPECT_EQ(live.events.front()->seq(), 7u);
  auto limited = hub.read_after(7, 2);
  ASSERT_EQ(limited.events.size(), 2u);
  EXPECT_EQ(limited.events[1]->seq(), 9u);
  EXPECT_TRUE(hub.read_after(10, 100).events.empty());
}

TEST(EventHub, AResumedRunsRepeatsAreDroppedAndOlderEventsComeFromTheStore) {
  EventHub hub(/*floor_seq=*/50, 100);
  EXPECT_TRUE(hub.read_after(10, 100).behind);  // 11..50 live in the store only
  hub.publish(event(45));                       // re-emitted after a checkpoint at 44
  hub.publish(event(50));
  hub.publish(event(51));
  auto read = hub.read_after(50, 100);
  ASSERT_EQ(read.events.size(), 1u);
  EXPECT_EQ(read.events[0]->seq(), 51u);
}

TEST(EventHub, WakesAWaitingReaderOnEventsAndOnTheEnd) {
  EventHub hub;
  std::thread producer([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    hub.publish(event(1));
  });
  auto t0 = std::chrono::steady_clock::now();
  hub.wait(0, hub.state_version(), std::chrono::seconds(10));
  EXPECT_LT(std::chrono::steady_clock::now() - t0, std::chrono::seconds(5));
  EXPECT_EQ(hub.read_after(0, 10).events.size(), 1u);
  producer.join();
  v1::StateChange done;
  done.set_state(v1::RUN_STATE_SUCCEEDED);
  hub.set_state(done);
  EXPECT_TRUE(hub.closed());
  hub.wait(1, 0, std::chrono::seconds(10));  // returns at once
}

TEST(Scheduler, RunsInQueueOrderAtMostNAtOnce) {
  std::mutex m;
  std::vector<std::int64_t> started;
  std::atomic<int> active{0}, most{0};
  {
    Scheduler scheduler(2, 100, [&](std::int64_t id, RunControl&) {
      int now = ++active;
      int prev = most.load();
      while (now > prev && !most.compare_exchange_weak(prev, now)) {
      }
      {
        std::lock_guard lock(m);
        started.push_back(id);
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
      --active;
    });
    for (int i = 1; i <= 8; ++i) ASSERT_TRUE(scheduler.enqueue(i));
    for (int tries = 0; tries < 500; ++tries) {
      {
        std::lock_guard lock(m);
        if (started.size() == 8) break;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
  }
  ASSERT_EQ(started.size(), 8u);
  EXPECT_LE(most.load(), 2);
  // With two workers, a run never starts before one queued two places ahead of it.
  for (std::size_t i = 0; i < started.size(); ++i)
    for (std::size_t j = i + 2; j < started.size(); ++j) EXPECT_LT(started[i], started[j]);
}

TEST(Scheduler, RefusesBeyondTheQueueLimitAndCancelsQueuedAndRunningRuns) {
  std::atomic<bool> release{false};
  std::atomic<bool> saw_cancel{false};
  std::atomic<int> ran{0};
  Scheduler scheduler(1, 2, [&](std::int64_t id, RunControl& control) {
    ++ran;
    if (id == 1) {
      while (!control.cancel && !release) std::this_thread::sleep_for(std::chrono::milliseconds(1));
      saw_cancel = control.cancel.load();
    }
  });
  ASSERT_TRUE(scheduler.enqueue(1));
  while (scheduler.running().empty()) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  EXPECT_TRUE(scheduler.enqueue(2));
  EXPECT_TRUE(scheduler.enqueue(3));
  EXPECT_FALSE(scheduler.enqueue(4));  // two waiting already
  EXPECT_EQ(scheduler.queue_position(3), 2);
  EXPECT_EQ(scheduler.cancel(2), Scheduler::CancelResult::kDequeued);
  EXPECT_EQ(scheduler.cancel(99), Scheduler::CancelResult::kNotFound);
  EXPECT_EQ(scheduler.cancel(1), Scheduler::CancelResult::kSignalled);
  while (scheduler.queued() > 0 || !scheduler.running().empty())
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  scheduler.shutdown(false);
  EXPECT_TRUE(saw_cancel);
  EXPECT_EQ(ran.load(), 2);  // 1 and 3; 2 was cancelled while queued
}

TEST(Scheduler, ShutdownAsksRunningRunsToCheckpointAndStop) {
  std::atomic<bool> asked{false};
  std::atomic<bool> started{false};
  Scheduler scheduler(1, 10, [&](std::int64_t, RunControl& control) {
    started = true;
    while (!control.stop_after_checkpoint) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    asked = control.checkpoint_now.load();
  });
  scheduler.enqueue(1);
  scheduler.enqueue(2);
  while (!started) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  scheduler.shutdown(true);
  EXPECT_TRUE(asked);
  EXPECT_EQ(scheduler.queued(), 1u);  // run 2 stays queued (the store keeps it for the next start)
}

}  // namespace
}  // namespace kessler::server
