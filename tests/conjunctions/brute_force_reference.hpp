// The brute-force reference for conjunction detection: every pair of objects, every step, the distance
// of the same Hermite interpolants sampled densely over the whole run, each sampled minimum refined by
// bisection on the sign of the distance's slope. Slow, simple, and independent of the detector's grid,
// filters and root isolation.
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/conjunctions/encounter.hpp"
#include "core/population/population.hpp"

namespace kessler::testing {

struct ReferenceEvent {
  ObjectId id1, id2;
  double tca_s, distance_m, threshold_m;
};

class BruteForceReference {
 public:
  BruteForceReference(const Population& population, const std::vector<StateArrays>& snaps, double dt_s)
      : pop_(population), snaps_(snaps), dt_(dt_s), steps_(static_cast<int>(snaps.size()) - 1) {}

  // Position and velocity of object i at run time t on its Hermite curve (steps own [k dt, (k+1) dt)).
  void state(std::size_t i, double t, double r[3], double v[3]) const {
    int k = std::clamp(static_cast<int>(std::floor(t / dt_)), 0, steps_ - 1);
    const StateArrays& a = snaps_[static_cast<std::size_t>(k)];
    const StateArrays& b = snaps_[static_cast<std::size_t>(k) + 1];
    const double s = (t - k * dt_) / dt_;
    // Hermite basis written out on its own (not the detector's code).
    const double b00 = (1.0 + 2.0 * s) * (1.0 - s) * (1.0 - s), b10 = s * (1.0 - s) * (1.0 - s);
    const double b01 = s * s * (3.0 - 2.0 * s), b11 = s * s * (s - 1.0);
    const double e00 = 6.0 * s * (s - 1.0), e10 = (1.0 - s) * (1.0 - 3.0 * s);
    const double e01 = -e00, e11 = s * (3.0 * s - 2.0);
    const double pa[3] = {a.x[i], a.y[i], a.z[i]}, va[3] = {a.vx[i], a.vy[i], a.vz[i]};
    const double pb[3] = {b.x[i], b.y[i], b.z[i]}, vb[3] = {b.vx[i], b.vy[i], b.vz[i]};
    for (int c = 0; c < 3; ++c) {
      r[c] = b00 * pa[c] + b10 * dt_ * va[c] + b01 * pb[c] + b11 * dt_ * vb[c];
      v[c] = (e00 * pa[c] + e10 * dt_ * va[c] + e01 * pb[c] + e11 * dt_ * vb[c]) / dt_;
    }
  }
  double distance2(std::size_t i, std::size_t j, double t) const {
    double ri[3], vi[3], rj[3], vj[3];
    state(i, t, ri, vi);
    state(j, t, rj, vj);
    double d2 = 0.0;
    for (int c = 0; c < 3; ++c) d2 += (ri[c] - rj[c]) * (ri[c] - rj[c]);
    return d2;
  }
  double slope(std::size_t i, std::size_t j, double t) const {
    double ri[3], vi[3], rj[3], vj[3];
    state(i, t, ri, vi);
    state(j, t, rj, vj);
    double g = 0.0;
    for (int c = 0; c < 3; ++c) g += (ri[c] - rj[c]) * (vi[c] - vj[c]);
    return g;
  }

  // Every local minimum of every pair's distance in (0, T) within the pair's threshold.
  std::vector<ReferenceEvent> run(const ConjunctionSettings& settings, int samples_per_step) const {
    const std::size_t n = pop_.size();
    std::vector<ReferenceEvent> events;
    std::vector<double> reach(n);
    for (int k = 0; k < steps_; ++k) {
      const StateArrays& a = snaps_[static_cast<std::size_t>(k)];
      const StateArrays& b = snaps_[static_cast<std::size_t>(k) + 1];
      // Every point of a Hermite curve is within |p1 - p0| + dt (|v0| + |v1|) / 3 of p0.
      for (std::size_t i = 0; i < n; ++i)
        reach[i] =
            std::hypot(b.x[i] - a.x[i], b.y[i] - a.y[i], b.z[i] - a.z[i]) +
            dt_ * (std::hypot(a.vx[i], a.vy[i], a.vz[i]) + std::hypot(b.vx[i], b.vy[i], b.vz[i])) / 3.0;
      for (std::size_t i = 0; i < n; ++i) {
        for (std::size_t j = i + 1; j < n; ++j) {
          const double h = threshold(settings, i, j);
          const double dx = a.x[i] - a.x[j], dy = a.y[i] - a.y[j], dz = a.z[i] - a.z[j];
          const double far = h + reach[i] + reach[j];
          if (dx * dx + dy * dy + dz * dz > far * far) continue;
          scan_pair(i, j, k, h, samples_per_step, events);
        }
      }
    }
    return events;
  }

  double threshold(const ConjunctionSettings& s, std::size_t i, std::size_t j) const {
    return s.screening_distance_m > 0.0 ? s.screening_distance_m
                                        : s.kappa_max * (pop_.radius_m[i] + pop_.radius_m[j]);
  }

 private:
  void scan_pair(std::size_t i, std::size_t j, int k, double h, int m_count,
                 std::vector<ReferenceEvent>& out) const {
    const double t0 = k * dt_, dt_sample = dt_ / m_count;
    const bool last_step = k == steps_ - 1;
    std::vector<double> d2(static_cast<std::size_t>(m_count) + 2);
    for (int m = 0; m <= m_count + 1; ++m) {
      if (m == m_count + 1 && last_step) break;
      d2[static_cast<std::size_t>(m)] = distance2(i, j, t0 + m * dt_sample);
    }
    for (int m = 1; m <= m_count; ++m) {
      if (m == m_count && last_step) break;
      const std::size_t u = static_cast<std::size_t>(m);
      if (!(d2[u - 1] > d2[u] && d2[u] <= d2[u + 1])) continue;
      // Bisection on the slope's sign between the neighbouring samples.
      double lo = t0 + (m - 1) * dt_sample, hi = t0 + (m + 1) * dt_sample;
      for (int it = 0; it < 60; ++it) {
        const double mid = 0.5 * (lo + hi);
        (slope(i, j, mid) < 0.0 ? lo : hi) = mid;
      }
      const double t = 0.5 * (lo + hi);
      const double d = std::sqrt(distance2(i, j, t));
      if (d <= h * (1.0 + 1e-9))
        out.push_back(
            ReferenceEvent{std::min(pop_.id[i], pop_.id[j]), std::max(pop_.id[i], pop_.id[j]), t, d, h});
    }
  }

  const Population& pop_;
  const std::vector<StateArrays>& snaps_;
  double dt_;
  int steps_;
};

}  // namespace kessler::testing
