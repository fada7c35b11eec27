#include "core/conjunctions/grid_balance.hpp"

#include <algorithm>

namespace kessler::grid {
namespace {

// The regions' histogram spans the last one's central 99 % widened by kHistogramMargin of that on each
// side.
constexpr double kHistogramMargin = 0.125;

// costs[0, count) each moved by kCostSmoothing towards measured(i) (set to it where still 0), then
// clamped within kCostSpread of their mean.
template <typename Measured>
void smooth_costs(double* costs, std::size_t count, Measured measured) {
  double mean = 0.0;
  for (std::size_t i = 0; i < count; ++i) {
    const double now = measured(i);
    costs[i] = costs[i] > 0.0 ? costs[i] + kCostSmoothing * (now - costs[i]) : now;
    mean += costs[i];
  }
  mean /= static_cast<double>(count);
  for (std::size_t i = 0; i < count; ++i)
    costs[i] = std::clamp(costs[i], mean / kCostSpread, mean * kCostSpread);
}

// The borders [m] of `regions` regions along x that hold shares of a histogram's objects (`bins` bins of
// `width` from `origin`) in proportion to `shares` (one per region), each border placed inside its bin as
// if the bin's objects were spread evenly across it. An empty histogram spreads the borders evenly over
// its range.
void region_borders_m(const std::uint32_t* hist, std::size_t bins, double origin, double width,
                      std::size_t regions, const double* shares, double* borders_m) {
  double total = 0.0;
  for (std::size_t b = 0; b < bins; ++b) total += hist[b];
  // Border k goes after the objects of the regions below it: their shares' part of the total.
  double all_shares = 0.0;
  for (std::size_t r = 0; r < regions; ++r) all_shares += shares[r];
  std::size_t border = 1;
  if (total > 0.0) {
    double shares_below = shares[0];  // of the regions below the next border
    double target = total * shares_below / all_shares;
    double below = 0.0;
    for (std::size_t b = 0; b < bins && border < regions; ++b) {
      const double in_bin = hist[b];
      while (border < regions && below + in_bin >= target) {
        const double fraction = in_bin > 0.0 ? (target - below) / in_bin : 0.0;
        borders_m[border++ - 1] = origin + (static_cast<double>(b) + fraction) * width;
        if (border < regions) {
          shares_below += shares[border - 1];
          target = total * shares_below / all_shares;
        }
      }
      below += in_bin;
    }
  }
  for (; border < regions; ++border)
    borders_m[border - 1] = origin + static_cast<double>(bins) * width * static_cast<double>(border) /
                                         static_cast<double>(regions);
}

// A histogram's bins for the next build: the range of the last one's central 99 % (0.5 % of the objects
// may lie beyond any bound: objects far out, on escape orbits or diverging, would otherwise stretch the
// bins until all others share one), widened by an eighth on each side, and twice as wide on a side
// whose end bin holds more (objects clamped there). Unchanged when the last one is empty.
void histogram_bins_m(const std::uint32_t* hist, std::size_t bins, double origin, double width,
                      double& next_origin, double& next_width) {
  double total = 0.0;
  for (std::size_t b = 0; b < bins; ++b) total += hist[b];
  if (!(total > 0.0)) return;
  const double tail = 0.005 * total;
  std::size_t low = 0, high = bins - 1;
  for (double below = 0.0; low + 1 < bins && below + hist[low] <= tail; ++low) below += hist[low];
  for (double above = 0.0; high > low && above + hist[high] <= tail; --high) above += hist[high];
  double lo = origin + static_cast<double>(low) * width, hi = origin + static_cast<double>(high + 1) * width;
  const double span = hi - lo;
  if (low == 0) lo -= span;
  if (high == bins - 1) hi += span;
  const double margin = kHistogramMargin * (hi - lo);
  next_origin = lo - margin;
  next_width = (hi - lo + 2.0 * margin) / static_cast<double>(bins);
}

}  // namespace

void RegionBalance::prepare(std::size_t regions, std::size_t team) {
  if (regions != costed_regions_) {  // costs measured for other regions say nothing of these
    std::fill(std::begin(cost_per_slot_s_), std::end(cost_per_slot_s_), 0.0);
    costed_regions_ = regions;
  }
  hist_.resize(kHistogramBins);
  thread_hist_.resize(team * kHistogramBins);
}

void RegionBalance::shares(std::size_t regions, double* shares) const {
  for (std::size_t r = 0; r < regions; ++r)
    shares[r] = cost_per_slot_s_[r] > 0.0 ? 1.0 / cost_per_slot_s_[r] : 1.0;
}

void RegionBalance::borders_from_last(std::size_t regions, const double* shares, double* borders_m,
                                      double& bin_origin_m, double& bin_width_m) const {
  region_borders_m(hist_.data(), kHistogramBins, hist_origin_m_, hist_width_m_, regions, shares, borders_m);
  histogram_bins_m(hist_.data(), kHistogramBins, hist_origin_m_, hist_width_m_, bin_origin_m, bin_width_m);
}

std::uint32_t RegionBalance::summed_bin(std::size_t b, std::size_t threads) const {
  std::uint32_t total = 0;
  for (std::size_t u = 0; u < threads; ++u) total += thread_hist_[u * kHistogramBins + b];
  return total;
}

void RegionBalance::borders_from_this(std::size_t regions, std::size_t threads, const double* shares,
                                      double bin_origin_m, double bin_width_m, double* borders_m) const {
  std::uint32_t hist[kHistogramBins];
  for (std::size_t b = 0; b < kHistogramBins; ++b) hist[b] = summed_bin(b, threads);
  region_borders_m(hist, kHistogramBins, bin_origin_m, bin_width_m, regions, shares, borders_m);
}

void RegionBalance::sample(std::size_t t, const float* lo_x, const char* oversized, std::size_t begin,
                           std::size_t end, double bin_origin_m, double bin_width_m) {
  std::uint32_t local_hist[kHistogramBins] = {};
  const double inverse_bin = 1.0 / bin_width_m;
  for (std::size_t i = begin; i < end; i += kHistogramStride) {
    if (oversized[i]) continue;
    const float x = lo_x[i];
    const double q = (x - bin_origin_m) * inverse_bin;
    ++local_hist[q <= 0.0 ? 0 : q >= kHistogramBins - 1 ? kHistogramBins - 1 : static_cast<std::size_t>(q)];
  }
  std::copy(local_hist, local_hist + kHistogramBins, &thread_hist_[t * kHistogramBins]);
}

void RegionBalance::sum_slice(std::size_t t, std::size_t threads) {
  for (std::size_t b = kHistogramBins * t / threads; b < kHistogramBins * (t + 1) / threads; ++b)
    hist_[b] = summed_bin(b, threads);
}

double RegionBalance::central_span_m(double bin_width_m) {
  return static_cast<double>(kHistogramBins) * bin_width_m / (1.0 + 2.0 * kHistogramMargin);
}

void RegionBalance::record(const double* seconds, const std::size_t* slots, std::size_t regions) {
  for (std::size_t r = 0; r < regions; ++r)
    if (slots[r] == 0 || !(seconds[r] > 0.0)) return;
  smooth_costs(cost_per_slot_s_, regions,
               [&](std::size_t r) { return seconds[r] / static_cast<double>(slots[r]); });
}

ThreadChunk PassBalance::chunk(const ChunkLayout* layout, std::size_t n, std::size_t t,
                               std::size_t team) const {
  if (team < 2 || team != costed_team_) return thread_chunk(layout, n, t, team);
  // Chunk u's objects weighted by 1 / its thread's cost per object: chunk k starts where the weighted
  // objects below it make k / team of the whole. Every thread computes the same starts.
  double below_t = 0.0, below_next = 0.0, total = 0.0;
  for (std::size_t u = 0; u < team; ++u) {
    const ThreadChunk c = thread_chunk(layout, n, u, team);
    const double weighted = static_cast<double>(c.end - c.begin) / cost_per_object_s_[u];
    if (u < t) below_t += weighted;
    if (u <= t) below_next += weighted;
    total += weighted;
  }
  auto start = [&](double weighted_below) {
    const auto i = static_cast<std::size_t>(static_cast<double>(n) * (weighted_below / total));
    return std::min(n, i) / kChunkAlign * kChunkAlign;
  };
  return {t == 0 ? 0 : start(below_t), t + 1 == team ? n : start(below_next)};
}

void PassBalance::record(const double* seconds, const std::size_t* objects, std::size_t team) {
  if (team > thread_pass_.size()) thread_pass_.resize(team);
  for (std::size_t u = 0; u < team; ++u) thread_pass_[u] = ThreadPass{seconds[u], objects[u]};
  record(team);
}

void PassBalance::record(std::size_t team) {
  if (team < 2 || team > thread_pass_.size()) return;
  // A chunk emptied (or not timed): keep the last costs.
  for (std::size_t u = 0; u < team; ++u)
    if (thread_pass_[u].objects == 0 || !(thread_pass_[u].seconds > 0.0)) return;
  if (team != costed_team_) {  // costs measured with another team say nothing of this one's
    cost_per_object_s_.assign(team, 0.0);
    costed_team_ = team;
  }
  smooth_costs(cost_per_object_s_.data(), team, [&](std::size_t u) {
    return thread_pass_[u].seconds / static_cast<double>(thread_pass_[u].objects);
  });
}

}  // namespace kessler::grid
