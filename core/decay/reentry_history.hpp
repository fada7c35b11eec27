// A decay prediction held against what the sky did: which objects a run burnt up, and when, against the
// decay dates a later SATCAT records (the check in tests/bench/bench_decay_history.cpp).
//  - Re-entries: the objects that really re-entered in (start, end] among those simulated (observed),
//    those the run burnt up by the end (predicted), and both (hits); recall = hits / observed, precision =
//    hits / predicted.
//  - Dates, for the hits: |predicted - observed| / (observed - start), the error as a fraction of the time
//    from the epoch; median and 90th percentile.
//  - A cloud: the fraction of its pieces on orbit at a base date still on orbit at later dates.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "core/population/population.hpp"
#include "core/time/epoch.hpp"

namespace kessler {

struct ReentryMonth {
  std::string month;  // "2019-04"
  std::int64_t predicted = 0, observed = 0;
};

struct ReentryComparison {
  std::int64_t simulated = 0, predicted = 0, observed = 0, hits = 0;
  double recall = 0.0, precision = 0.0;
  double median_date_error = 0.0, p90_date_error = 0.0;  // fractions of the time from the start
  std::vector<ReentryMonth> by_month;                    // start's month to end's, in order
};

// simulated_ids: every object the run started with; burn_up_s: object -> burn-up time [s after start]
// (objects absent did not burn up); observed_decay: object -> decay date (any object; those not simulated
// or outside (start, end] are ignored).
ReentryComparison compare_reentries(const std::vector<ObjectId>& simulated_ids,
                                    const std::map<ObjectId, double>& burn_up_s,
                                    const std::unordered_map<ObjectId, UtcEpoch>& observed_decay,
                                    const UtcEpoch& start, const UtcEpoch& end);

// The fraction of `pieces` on orbit at `base` that are still on orbit at `at`; a piece leaves at its
// removal time (nullopt: never). 0 when none is on orbit at base.
double fraction_still_on_orbit(const std::vector<std::optional<UtcEpoch>>& removal, const UtcEpoch& base,
                               const UtcEpoch& at);

}  // namespace kessler
