// Limits that keep one client from hurting the others: per token, runs queued and running, watch
// streams and the rate of expensive requests; daemon-wide, watch streams. A limit reached is a
// LimitError whose message names the limit, its flag and its value (RESOURCE_EXHAUSTED on the wire).
#pragma once

#include <chrono>
#include <cstdint>
#include <map>
#include <mutex>
#include <stdexcept>
#include <string>

#include "server/auth.hpp"

namespace kessler::server {

struct LimitError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct LimitOptions {
  // Per token (read and submit tokens; the admin and the tokenless default are the operator and
  // are held only by the daemon-wide limits). 0: no limit.
  std::uint64_t runs_per_token = 100;    // queued + running, ensemble members included
  std::uint64_t watches_per_token = 32;  // WatchRun streams open at once
  double requests_per_s_per_token = 20;  // expensive RPCs (submissions, queries), bursts of 2 s
  // Daemon-wide, every caller: WatchRun streams open at once (each holds a thread). 0: no limit.
  std::uint64_t watches = 512;
};

class Limits {
 public:
  explicit Limits(LimitOptions options = {}) : options_(options) {}
  const LimitOptions& options() const { return options_; }

  // Throws LimitError when the caller already has `active` runs and `adding` more would pass its limit.
  void check_runs(const Caller& caller, std::uint64_t active, std::uint64_t adding) const;
  // Takes one request from the caller's budget of expensive requests, or throws LimitError.
  void take_request(const Caller& caller);

  // One open watch stream, counted while it lives; the constructor throws LimitError at a limit.
  class Watch {
   public:
    Watch(Limits& limits, const Caller& caller);
    ~Watch();
    Watch(const Watch&) = delete;
    Watch& operator=(const Watch&) = delete;

   private:
    Limits& limits_;
    std::string key_;
    bool per_token_;
  };
  std::uint64_t watches_open() const;

 private:
  static bool held(const Caller& caller) { return !caller.anonymous && caller.role != Role::kAdmin; }
  struct Bucket {
    double tokens = 0;
    std::chrono::steady_clock::time_point refilled;
  };
  LimitOptions options_;
  mutable std::mutex mutex_;
  std::map<std::string, Bucket> buckets_;
  std::map<std::string, std::uint64_t> watches_by_token_;
  std::uint64_t watches_total_ = 0;
};

}  // namespace kessler::server
