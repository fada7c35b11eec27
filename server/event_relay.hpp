// The sink of one running run: takes the simulation's events off its thread.
//
// The simulation thread only appends each event, as the core hands it over, to a pending list (one
// uncontended lock, no allocation of wire messages, at most one wake-up per batch). A relay thread
// gathers what a few milliseconds of simulation produce, turns it into wire messages and hands the
// whole batch to the Store (one queue operation) and to the run's EventHub (one lock, one wake-up of
// the watchers). So watchers and the store cost the simulation thread nothing but the append, and a
// step's burst of events reaches the watchers as one batch.
//
// Order is kept: events and checkpoints reach the store in the order the simulation emitted them (a
// checkpoint after every event before it), and the hub in increasing sequence numbers.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "core/simulation/events.hpp"
#include "core/simulation/simulation.hpp"
#include "server/event_hub.hpp"
#include "server/store.hpp"

namespace kessler::server {

class EventRelay final : public EventSink {
 public:
  // `gather`: how long the relay lets events accumulate after the first one of a batch; the latency
  // it adds to a watcher's view, and what divides the number of batches (and wake-ups).
  // `checkpoint_interval`: the store's minimum interval between a run's checkpoint writes. A
  // checkpoint that comes sooner than this after the last one taken over would only wait in the store
  // to be replaced by the next: it is not copied at all (the one cost a checkpoint has on the
  // simulation's thread), unless `control` says the run stops after it. So the stored checkpoint is
  // at most this interval plus the spacing of the run's checkpoints behind the newest taken.
  EventRelay(std::int64_t run_id, EventHub& hub, Store& store,
             std::chrono::milliseconds gather = std::chrono::milliseconds(50),
             std::chrono::milliseconds checkpoint_interval = std::chrono::milliseconds(0),
             const RunControl* control = nullptr);
  ~EventRelay() override;  // drain()
  EventRelay(const EventRelay&) = delete;
  EventRelay& operator=(const EventRelay&) = delete;

  // From the simulation's thread.
  void on_encounter(std::uint64_t seq, const Encounter& encounter) override;
  void on_burn_up(std::uint64_t seq, const BurnUp& burn_up) override;
  void on_progress(std::uint64_t seq, const Progress& progress) override;
  void on_breakup(std::uint64_t seq, const BreakupReport& breakup) override;
  void on_lifecycle(std::uint64_t seq, const LifecycleReport& event) override;
  void on_checkpoint(std::uint64_t last_seq, std::int64_t step, const std::string& bytes) override;
  // Handed to the store in order with the events (the store encodes it on its writer thread).
  void on_snapshot(const std::shared_ptr<const PopulationSnapshot>& snapshot) override;
  void on_finished(const RunSummary&) override {}
  void on_failed(const std::string& reason) override;

  // Blocks until everything handed over so far is in the hub and queued in the store (not yet
  // committed: Store::flush does that), then stops the relay thread. Call when the run has returned.
  void drain();

  std::string failure() const;
  // CPU seconds the relay thread used (after drain()).
  double cpu_s() const;

 private:
  // One item as the simulation handed it over (the core's own types: no wire work on its thread).
  struct Item {
    enum class Kind : std::uint8_t {
      kEncounter,
      kBurnUp,
      kProgress,
      kBreakup,
      kLifecycle,
      kCheckpoint,
      kSnapshot
    };
    Kind kind = Kind::kEncounter;
    std::uint64_t seq = 0;  // last_seq for a checkpoint
    Encounter encounter;
    BurnUp burn_up;
    Progress progress;
    std::shared_ptr<const BreakupReport> breakup;  // with its fragments
    LifecycleReport lifecycle;
    std::int64_t step = 0;
    std::shared_ptr<const std::string> checkpoint;
    std::shared_ptr<const PopulationSnapshot> snapshot;
  };
  void push(Item&& item);
  void relay_loop();
  void hand_over(std::vector<Item>& items);

  std::int64_t run_id_;
  EventHub& hub_;
  Store& store_;
  std::chrono::milliseconds gather_;
  std::chrono::milliseconds checkpoint_interval_;
  const RunControl* control_;
  std::chrono::steady_clock::time_point last_checkpoint_taken_{};  // simulation thread only
  bool took_checkpoint_ = false;                                   // simulation thread only

  mutable std::mutex mutex_;
  std::condition_variable cv_;       // the relay waits here for work
  std::condition_variable done_cv_;  // drain() waits here
  std::vector<Item> pending_;
  bool relay_idle_ = false;  // the relay sleeps until the next item: the next push wakes it
  bool draining_ = false;
  bool stopped_ = false;
  std::uint64_t pushed_ = 0;
  std::uint64_t handed_over_ = 0;
  std::string failure_;
  double cpu_s_ = 0;
  std::thread relay_;
};

}  // namespace kessler::server
