#include "core/decay/reentry_history.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <unordered_set>

namespace kessler {
namespace {

std::string month_of(const UtcEpoch& when) {
  int year = 0, month = 0, day = 0, hour = 0, minute = 0;
  double second = 0.0;
  when.to_calendar(year, month, day, hour, minute, second);
  char text[16];
  std::snprintf(text, sizeof text, "%04d-%02d", year, month);
  return text;
}

double quantile(std::vector<double> values, double q) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  const double at = q * static_cast<double>(values.size() - 1);
  const auto lo = static_cast<std::size_t>(std::floor(at));
  const std::size_t hi = std::min(lo + 1, values.size() - 1);
  return values[lo] + (at - static_cast<double>(lo)) * (values[hi] - values[lo]);
}

}  // namespace

ReentryComparison compare_reentries(const std::vector<ObjectId>& simulated_ids,
                                    const std::map<ObjectId, double>& burn_up_s,
                                    const std::unordered_map<ObjectId, UtcEpoch>& observed_decay,
                                    const UtcEpoch& start, const UtcEpoch& end) {
  ReentryComparison out;
  const double window_s = end.seconds_since(start);
  std::map<std::string, ReentryMonth> months;
  for (UtcEpoch m = start; m.seconds_since(end) <= 0.0; m = m.plus_seconds(86400.0))
    months[month_of(m)].month = month_of(m);
  std::vector<double> errors;
  for (ObjectId id : simulated_ids) {
    ++out.simulated;
    const auto b = burn_up_s.find(id);
    const bool predicted = b != burn_up_s.end() && b->second <= window_s;
    const auto o = observed_decay.find(id);
    const double observed_s = o == observed_decay.end() ? -1.0 : o->second.seconds_since(start);
    const bool observed = observed_s > 0.0 && observed_s <= window_s;
    if (predicted) {
      ++out.predicted;
      ++months[month_of(start.plus_seconds(b->second))].predicted;
    }
    if (observed) {
      ++out.observed;
      ++months[month_of(o->second)].observed;
    }
    if (predicted && observed) {
      ++out.hits;
      errors.push_back(std::fabs(b->second - observed_s) / observed_s);
    }
  }
  out.recall = out.observed > 0 ? static_cast<double>(out.hits) / static_cast<double>(out.observed) : 0.0;
  out.precision =
      out.predicted > 0 ? static_cast<double>(out.hits) / static_cast<double>(out.predicted) : 0.0;
  out.median_date_error = quantile(errors, 0.5);
  out.p90_date_error = quantile(errors, 0.9);
  for (auto& [key, month] : months) out.by_month.push_back(month);
  return out;
}

double fraction_still_on_orbit(const std::vector<std::optional<UtcEpoch>>& removal, const UtcEpoch& base,
                               const UtcEpoch& at) {
  std::int64_t at_base = 0, still = 0;
  for (const auto& r : removal) {
    if (r && r->seconds_since(base) <= 0.0) continue;
    ++at_base;
    if (!r || r->seconds_since(at) > 0.0) ++still;
  }
  return at_base > 0 ? static_cast<double>(still) / static_cast<double>(at_base) : 0.0;
}

}  // namespace kessler
