#include "server/event_hub.hpp"

#include <algorithm>

#include "server/store.hpp"

namespace kessler::server {

EventHub::EventHub(std::uint64_t floor_seq, std::size_t capacity)
    : capacity_(std::max<std::size_t>(capacity, 1)), evicted_upto_(floor_seq), last_seq_(floor_seq) {}

void EventHub::append_locked(EventPtr event) {
  if (event->seq() <= last_seq_) return;  // a resumed run repeating what watchers already have
  last_seq_ = event->seq();
  window_.push_back(std::move(event));
  if (window_.size() > capacity_) {
    evicted_upto_ = window_.front()->seq();
    window_.pop_front();
  }
}

void EventHub::publish(EventPtr event) {
  {
    std::lock_guard lock(mutex_);
    append_locked(std::move(event));
  }
  cv_.notify_all();
}

void EventHub::publish(const std::vector<EventPtr>& events) {
  if (events.empty()) return;
  {
    std::lock_guard lock(mutex_);
    for (const EventPtr& e : events) append_locked(e);
  }
  cv_.notify_all();
}

void EventHub::set_state(const v1::StateChange& state) {
  {
    std::lock_guard lock(mutex_);
    state_ = state;
    ++state_version_;
    if (is_terminal(state.state())) closed_ = true;
  }
  cv_.notify_all();
}

v1::StateChange EventHub::state() const {
  std::lock_guard lock(mutex_);
  return state_;
}

bool EventHub::closed() const {
  std::lock_guard lock(mutex_);
  return closed_;
}

std::uint64_t EventHub::state_version() const {
  std::lock_guard lock(mutex_);
  return state_version_;
}

std::uint64_t EventHub::last_seq() const {
  std::lock_guard lock(mutex_);
  return last_seq_;
}

EventHub::Read EventHub::read_after(std::uint64_t after, std::size_t limit) const {
  Read read;
  std::lock_guard lock(mutex_);
  if (after < evicted_upto_) {
    read.behind = true;
    return read;
  }
  auto first = std::upper_bound(window_.begin(), window_.end(), after,
                                [](std::uint64_t seq, const EventPtr& e) { return seq < e->seq(); });
  for (auto it = first; it != window_.end() && read.events.size() < limit; ++it) read.events.push_back(*it);
  return read;
}

void EventHub::wait(std::uint64_t after, std::uint64_t state_version,
                    std::chrono::milliseconds timeout) const {
  std::unique_lock lock(mutex_);
  cv_.wait_for(lock, timeout,
               [&] { return closed_ || last_seq_ > after || state_version_ != state_version; });
}

}  // namespace kessler::server
