// A queue of runs and a fixed number of workers: runs start in the order they were queued, at most
// `workers` at a time. What a run does is the caller's `Work`; the scheduler only orders, starts,
// cancels and stops.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

#include "core/simulation/simulation.hpp"

namespace kessler::server {

class Scheduler {
 public:
  // Runs one run to its end on a worker thread; polls `control` (cancel, stop_after_checkpoint).
  using Work = std::function<void(std::int64_t run_id, RunControl& control)>;

  Scheduler(int workers, std::size_t queue_limit, Work work);
  ~Scheduler();  // shutdown(false) unless done before

  // False when the queue already holds queue_limit runs (unless ignore_limit: recovery at start).
  bool enqueue(std::int64_t run_id, bool ignore_limit = false);

  enum class CancelResult { kNotFound, kDequeued, kSignalled };
  // A queued run leaves the queue (its Work never runs); a running one gets control.cancel.
  CancelResult cancel(std::int64_t run_id);

  // Stops taking runs from the queue and waits for the running ones to return. With checkpoint, each
  // running run is asked to checkpoint and stop (it stays resumable); without, to cancel.
  void shutdown(bool checkpoint);

  std::size_t queued() const;
  // 1-based position in the queue, 0 when not queued.
  int queue_position(std::int64_t run_id) const;
  std::vector<std::int64_t> running() const;

 private:
  void worker_loop();

  Work work_;
  std::size_t queue_limit_;
  mutable std::mutex mutex_;
  std::condition_variable cv_;
  std::deque<std::int64_t> queue_;
  std::map<std::int64_t, std::shared_ptr<RunControl>> running_;
  bool stopping_ = false;
  std::vector<std::thread> workers_;
};

}  // namespace kessler::server
