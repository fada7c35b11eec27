// Per run, a bounded in-memory window of the most recent events, for watchers that keep up.
//
// The simulation publishes into the hub and never waits for a watcher: when the window is full the
// oldest event leaves it. A watcher whose cursor falls behind the window (or who reconnects with an
// old sequence number) reads the missing stretch from the Store and comes back to the hub.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <vector>

#include "kessler/v1/service.pb.h"

namespace kessler::server {

using EventPtr = std::shared_ptr<const v1::RunEvent>;

class EventHub {
 public:
  // `floor_seq`: events up to this number were emitted before the hub existed (a resumed run): they
  // live in the store only. `capacity`: events kept in memory.
  explicit EventHub(std::uint64_t floor_seq = 0, std::size_t capacity = 65536);

  // From the simulation's thread. Events must come in increasing seq, except that a resumed run may
  // repeat numbers it emitted before (those are dropped here: watchers have them).
  void publish(EventPtr event);
  // A batch in increasing seq: one lock and one wake-up of the watchers for all of it.
  void publish(const std::vector<EventPtr>& events);
  // The run has changed state (also wakes watchers). A terminal state closes the hub.
  void set_state(const v1::StateChange& state);
  v1::StateChange state() const;
  bool closed() const;

  struct Read {
    std::vector<EventPtr> events;  // seq > after, in order
    bool behind = false;           // events after `after` left the window: read the store first
  };
  // Up to `limit` events after `after`, without waiting.
  Read read_after(std::uint64_t after, std::size_t limit) const;
  // Waits until there is an event after `after`, a state change newer than `state_version`, the hub
  // closes, or the timeout passes.
  void wait(std::uint64_t after, std::uint64_t state_version, std::chrono::milliseconds timeout) const;
  std::uint64_t state_version() const;
  std::uint64_t last_seq() const;

 private:
  void append_locked(EventPtr event);

  mutable std::mutex mutex_;
  mutable std::condition_variable cv_;
  std::deque<EventPtr> window_;
  std::size_t capacity_;
  std::uint64_t evicted_upto_;  // every event with seq <= this is out of the window (or never in it)
  std::uint64_t last_seq_;
  v1::StateChange state_;
  std::uint64_t state_version_ = 0;
  bool closed_ = false;
};

}  // namespace kessler::server
