// Monte Carlo ensembles: N runs of one scenario that differ only in their seed, and the aggregates
// over the members that succeeded. The RunManager's ensemble calls (ensembles.cpp) queue the members
// as ordinary runs and compute the aggregates from the store on every GetEnsemble; the pure parts
// (percentiles, the series) are here to be tested on their own.
#pragma once

#include <cstdint>
#include <map>
#include <vector>

#include "kessler/v1/service.pb.h"
#include "server/store.hpp"

namespace kessler::server {

// The p-quantile (0 <= p <= 1) of ascending values by linear interpolation between order statistics
// (Hyndman & Fan type 7, numpy's default): h = (n - 1) p, q = x[floor h] + (h - floor h)
// (x[floor h + 1] - x[floor h]) with x 0-based. The median is p = 0.5. 0 for no values.
double percentile(const std::vector<double>& sorted, double p);

// The times at which every member has a progress sample, ascending (members of one scenario share
// their progress times; a member that ended early bounds the series).
std::vector<double> common_times(const std::vector<MemberResults>& members);

// The ensemble's series over `members` at their common times: objects on orbit (mean, median, 5th
// and 95th percentiles), by type (means), cumulative collisions, catastrophic collisions and
// conjunctions per kappa threshold (means; an event counts at t when its time is <= t).
std::vector<v1::EnsembleSample> aggregate_series(const std::vector<MemberResults>& members);

// The ensemble's state from its members' (counts by state): queued while none has started; running
// while some member has not ended; else failed if one failed, cancelled if one was cancelled,
// succeeded. An ensemble with no stored members reads as succeeded.
v1::RunState ensemble_state(const std::map<v1::RunState, std::uint64_t>& counts);

}  // namespace kessler::server
