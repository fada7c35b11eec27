// The RunManager's side of store faults: runs whose events could not be written fail with the error,
// submissions wait (UNAVAILABLE) while the store cannot write, ends the store could not take are kept
// and written when it can, a probe every --store-probe-interval learns when space returned, and
// quarantined runs (store_health.hpp) answer no queries.
#include <iostream>

#include "server/run_manager.hpp"

namespace kessler::server {

using Code = ServiceError::Code;

void RunManager::recover() {
  // Runs a previous daemon left running go first (they resume from their checkpoints), then the
  // queue in its order.
  auto interrupted = store_.runs_in_state(v1::RUN_STATE_RUNNING);
  auto waiting = store_.runs_in_state(v1::RUN_STATE_QUEUED);
  for (std::int64_t id : interrupted) store_.set_queued(id);
  for (std::int64_t id : interrupted) scheduler_->enqueue(id, true);
  for (std::int64_t id : waiting) scheduler_->enqueue(id, true);
}

void RunManager::note_store_failure(std::int64_t run_id, const std::string& error) {
  {
    std::lock_guard lock(faults_mutex_);
    if (store_failures_.count(run_id)) return;
    store_failures_[run_id] = "the store could not write the run's events (" + error + ")";
  }
  std::cerr << "kesslerd: run " << run_id << ": store write failed: " << error << std::endl;
  scheduler_->cancel(run_id);  // the run stops at the end of its step; execute() fails it
  health_cv_.notify_all();
}

std::optional<std::string> RunManager::take_store_failure(std::int64_t run_id) {
  std::lock_guard lock(faults_mutex_);
  auto it = store_failures_.find(run_id);
  if (it == store_failures_.end()) return std::nullopt;
  std::string error = it->second;
  store_failures_.erase(it);
  return error;
}

bool RunManager::store_writable() {
  return store_.health().writable();
}

void RunManager::require_writable() {
  if (store_.health().writable() || store_.probe_writable()) return;
  throw ServiceError(Code::kUnavailable, "the store cannot write (" + store_.health().error() +
                                             "); submissions are refused until it can, reads go on");
}

void RunManager::require_not_quarantined(std::int64_t run_id) {
  auto it = store_.quarantined_runs().find(run_id);
  if (it == store_.quarantined_runs().end()) return;
  throw ServiceError(Code::kFailedPrecondition,
                     "run " + std::to_string(run_id) + " is quarantined: the startup check found " +
                         it->second +
                         "; its stored results are not served (delete it, or restore the database)");
}

void RunManager::overlay_faults(v1::Run& run) {
  auto q = store_.quarantined_runs().find(run.id());
  if (q != store_.quarantined_runs().end()) run.set_error("quarantined: " + q->second);
  std::lock_guard lock(faults_mutex_);
  auto it = unrecorded_.find(run.id());
  if (it == unrecorded_.end()) return;
  run.set_state(it->second.state);
  run.set_error(it->second.error);
  if (it->second.summary) *run.mutable_summary() = *it->second.summary;
}

void RunManager::record_finish_later(std::int64_t run_id, v1::RunState state, const std::string& error,
                                     const v1::RunSummary* summary) {
  std::lock_guard lock(faults_mutex_);
  Unrecorded& u = unrecorded_[run_id];
  u.state = state;
  u.error = error;
  if (summary) u.summary = *summary;
}

void RunManager::write_unrecorded() {
  std::map<std::int64_t, Unrecorded> pending;
  {
    std::lock_guard lock(faults_mutex_);
    pending = unrecorded_;
  }
  for (const auto& [id, u] : pending) {
    try {
      store_.set_finished(
          id, u.state,
          std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count(), u.error,
          u.summary ? &*u.summary : nullptr);
      std::lock_guard lock(faults_mutex_);
      unrecorded_.erase(id);
    } catch (const StoreError& e) {
      store_.health().record_failure(e.what());
      return;
    }
  }
}

void RunManager::set_store_health_listener(std::function<void(bool)> listener) {
  std::lock_guard lock(faults_mutex_);
  health_listener_ = std::move(listener);
  if (health_listener_) health_listener_(store_.health().writable());
}

void RunManager::health_loop() {
  std::unique_lock lock(faults_mutex_);
  while (!health_stop_) {
    health_cv_.wait_for(lock, options_.store_probe_interval);
    if (health_stop_) break;
    lock.unlock();
    bool writable = store_.health().writable();
    if (!writable) writable = store_.probe_writable();
    bool recover_now = false;
    if (writable) {
      write_unrecorded();
      std::lock_guard again(faults_mutex_);
      recover_now = recovery_pending_;
      recovery_pending_ = false;
    }
    if (recover_now) {
      try {
        recover();
      } catch (const StoreError& e) {
        store_.health().record_failure(e.what());
        std::lock_guard again(faults_mutex_);
        recovery_pending_ = true;
      }
    }
    writable = store_.health().writable();
    lock.lock();
    if (writable != reported_writable_) {
      reported_writable_ = writable;
      std::cerr << "kesslerd: the store "
                << (writable ? "can write again" : "cannot write: " + store_.health().error()) << std::endl;
      if (health_listener_) health_listener_(writable);
    }
  }
}

void RunManager::start_health_thread() {
  health_thread_ = std::thread([this] { health_loop(); });
}

void RunManager::stop_health_thread() {
  {
    std::lock_guard lock(faults_mutex_);
    health_stop_ = true;
  }
  health_cv_.notify_all();
  if (health_thread_.joinable()) health_thread_.join();
}

}  // namespace kessler::server
