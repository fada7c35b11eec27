#include "server/scheduler.hpp"

#include <pthread.h>

#include <algorithm>

namespace kessler::server {

Scheduler::Scheduler(int workers, std::size_t queue_limit, Work work)
    : work_(std::move(work)), queue_limit_(queue_limit) {
  for (int i = 0; i < std::max(workers, 1); ++i)
    workers_.emplace_back([this] {
      pthread_setname_np(pthread_self(), "kessler-run");  // the simulation's thread, for top -H
      worker_loop();
    });
}

Scheduler::~Scheduler() {
  shutdown(false);
}

bool Scheduler::enqueue(std::int64_t run_id, bool ignore_limit) {
  {
    std::lock_guard lock(mutex_);
    if (!ignore_limit && queue_.size() >= queue_limit_) return false;
    queue_.push_back(run_id);
  }
  cv_.notify_one();
  return true;
}

Scheduler::CancelResult Scheduler::cancel(std::int64_t run_id) {
  std::lock_guard lock(mutex_);
  auto queued = std::find(queue_.begin(), queue_.end(), run_id);
  if (queued != queue_.end()) {
    queue_.erase(queued);
    return CancelResult::kDequeued;
  }
  auto running = running_.find(run_id);
  if (running == running_.end()) return CancelResult::kNotFound;
  running->second->cancel = true;
  return CancelResult::kSignalled;
}

void Scheduler::shutdown(bool checkpoint) {
  {
    std::lock_guard lock(mutex_);
    if (stopping_ && workers_.empty()) return;
    stopping_ = true;
    for (auto& [id, control] : running_) {
      if (checkpoint) {
        control->stop_after_checkpoint = true;
        control->checkpoint_now = true;
      } else {
        control->cancel = true;
      }
    }
  }
  cv_.notify_all();
  for (auto& t : workers_)
    if (t.joinable()) t.join();
  workers_.clear();
}

std::size_t Scheduler::queued() const {
  std::lock_guard lock(mutex_);
  return queue_.size();
}

int Scheduler::queue_position(std::int64_t run_id) const {
  std::lock_guard lock(mutex_);
  auto it = std::find(queue_.begin(), queue_.end(), run_id);
  return it == queue_.end() ? 0 : static_cast<int>(it - queue_.begin()) + 1;
}

std::vector<std::int64_t> Scheduler::running() const {
  std::lock_guard lock(mutex_);
  std::vector<std::int64_t> ids;
  for (const auto& [id, control] : running_) ids.push_back(id);
  return ids;
}

void Scheduler::worker_loop() {
  for (;;) {
    std::int64_t run_id = 0;
    std::shared_ptr<RunControl> control;
    {
      std::unique_lock lock(mutex_);
      cv_.wait(lock, [&] { return stopping_ || !queue_.empty(); });
      if (stopping_) return;
      run_id = queue_.front();
      queue_.pop_front();
      control = std::make_shared<RunControl>();
      running_[run_id] = control;
    }
    work_(run_id, *control);
    {
      std::lock_guard lock(mutex_);
      running_.erase(run_id);
    }
  }
}

}  // namespace kessler::server
