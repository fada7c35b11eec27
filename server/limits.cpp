#include "server/limits.hpp"

#include <algorithm>
#include <sstream>

namespace kessler::server {
namespace {

std::string number(double v) {
  std::ostringstream out;
  out << v;
  return out.str();
}

}  // namespace

void Limits::check_runs(const Caller& caller, std::uint64_t active, std::uint64_t adding) const {
  if (!held(caller) || options_.runs_per_token == 0) return;
  if (active + adding > options_.runs_per_token)
    throw LimitError("runs per token: token '" + caller.name + "' has " + std::to_string(active) +
                     " runs queued or running and asks for " + std::to_string(adding) +
                     " more; the limit is " + std::to_string(options_.runs_per_token) +
                     " (--max-runs-per-token)");
}

void Limits::take_request(const Caller& caller) {
  const double rate = options_.requests_per_s_per_token;
  if (!held(caller) || rate <= 0) return;
  const double burst = std::max(1.0, 2.0 * rate);
  const auto now = std::chrono::steady_clock::now();
  std::lock_guard lock(mutex_);
  auto [it, fresh] = buckets_.try_emplace(caller.name, Bucket{burst, now});
  Bucket& b = it->second;
  if (!fresh) {
    const double elapsed_s = std::chrono::duration<double>(now - b.refilled).count();
    b.tokens = std::min(burst, b.tokens + elapsed_s * rate);
    b.refilled = now;
  }
  if (b.tokens < 1.0)
    throw LimitError("requests per second: token '" + caller.name + "' is above " + number(rate) +
                     " expensive requests per second (--max-requests-per-s); retry later");
  b.tokens -= 1.0;
}

Limits::Watch::Watch(Limits& limits, const Caller& caller)
    : limits_(limits), key_(caller.name), per_token_(held(caller)) {
  const LimitOptions& o = limits.options_;
  std::lock_guard lock(limits.mutex_);
  if (o.watches > 0 && limits.watches_total_ >= o.watches)
    throw LimitError("watch streams: the daemon has " + std::to_string(limits.watches_total_) +
                     " open, its limit (--max-watches " + std::to_string(o.watches) + ")");
  if (per_token_ && o.watches_per_token > 0 && limits.watches_by_token_[key_] >= o.watches_per_token)
    throw LimitError("watch streams per token: token '" + key_ + "' has " +
                     std::to_string(limits.watches_by_token_[key_]) +
                     " open, its limit (--max-watches-per-token " + std::to_string(o.watches_per_token) +
                     ")");
  ++limits.watches_total_;
  if (per_token_) ++limits.watches_by_token_[key_];
}

Limits::Watch::~Watch() {
  std::lock_guard lock(limits_.mutex_);
  --limits_.watches_total_;
  if (per_token_ && --limits_.watches_by_token_[key_] == 0) limits_.watches_by_token_.erase(key_);
}

std::uint64_t Limits::watches_open() const {
  std::lock_guard lock(mutex_);
  return watches_total_;
}

}  // namespace kessler::server
