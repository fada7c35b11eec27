// Store::event_times: when the run's launches, re-entries and breakups happened, for the figures'
// markers. Burn-ups keep their time only in the event's payload; the others have it in a column.
#include "server/store.hpp"
#include "server/store_internal.hpp"

namespace kessler::server {

using namespace detail;

EventTimes Store::event_times(std::int64_t run_id) {
  EventTimes out;
  Lease lease(*this);
  Statement burn_ups(lease.db(), "SELECT payload FROM events WHERE run_id = ? AND kind = 3 ORDER BY seq");
  burn_ups.bind(1, run_id);
  while (burn_ups.step()) {
    v1::RunEvent event;
    if (event.ParseFromString(burn_ups.text(0)) && event.has_burn_up())
      out.burn_ups_s.push_back(event.burn_up().time_s());
  }
  Statement breakups(lease.db(), "SELECT time_s FROM breakups WHERE run_id = ? ORDER BY breakup_id");
  breakups.bind(1, run_id);
  while (breakups.step()) out.breakups_s.push_back(breakups.f64(0));
  // Launches (kind 0) with the objects they brought, de-orbits (kind 4).
  Statement lifecycle(lease.db(),
                      "SELECT kind, time_s, last_id - first_id + 1 FROM lifecycle_events WHERE run_id = ? "
                      "AND kind IN (0, 4) ORDER BY seq");
  lifecycle.bind(1, run_id);
  while (lifecycle.step()) {
    if (lifecycle.i64(0) == 0)
      out.launches.emplace_back(lifecycle.f64(1), static_cast<std::uint64_t>(lifecycle.i64(2)));
    else
      out.deorbits_s.push_back(lifecycle.f64(1));
  }
  return out;
}

}  // namespace kessler::server
