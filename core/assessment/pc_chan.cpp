#include "core/assessment/pc_chan.hpp"

#include "core/assessment/pc_foster.hpp"

#include <algorithm>
#include <cmath>

namespace kessler::assessment {

namespace {

// P(Poisson(mu) > m), from log p_{m+1}(mu), by the upper-tail series (no cancellation) when mu < m + 2.
double poisson_upper_tail_series(double mu, double m, double log_p_next) {
  double term = 1.0;
  double sum = 1.0;
  for (double j = m + 2.0; term > 1e-17 * sum && j < m + 2.0 + 400.0; j += 1.0) {
    term *= mu / j;
    sum += term;
  }
  return std::exp(log_p_next) * sum;
}

}  // namespace

double pc_chan(const EncounterGeometry& g, double hard_body_radius_m) {
  if (!(hard_body_radius_m > 0.0)) return 0.0;
  const double mu = 0.5 * hard_body_radius_m * hard_body_radius_m / (g.sigma_x_m * g.sigma_y_m);
  const double lambda = 0.5 * ((g.miss_x_m * g.miss_x_m) / (g.sigma_x_m * g.sigma_x_m) +
                               (g.miss_y_m * g.miss_y_m) / (g.sigma_y_m * g.sigma_y_m));
  // exp(-lambda) underflows: the series cannot start; the integral still can.
  if (lambda > 700.0) return pc_foster(g, hard_body_radius_m);
  const double log_lambda = std::log(lambda);
  const double log_mu = std::log(mu);
  double log_p = -lambda;            // log Poisson(m; lambda)
  double log_q_next = -mu + log_mu;  // log Poisson(m + 1; mu)
  double cdf_mu = std::exp(-mu);     // P(Poisson(mu) <= m), used while mu >= m + 2
  double sum = 0.0;
  double previous = 0.0;
  const double last = lambda + 40.0 * std::sqrt(lambda) + 60.0;
  for (double m = 0.0; m <= last; m += 1.0) {
    const double tail = mu < m + 2.0 ? poisson_upper_tail_series(mu, m, log_q_next) : 1.0 - cdf_mu;
    const double term = lambda > 0.0 ? std::exp(log_p) * tail : (m == 0.0 ? tail : 0.0);
    sum += term;
    if (lambda == 0.0) break;
    // The terms are log-concave in m: once they fall, the rest is at most term r / (1 - r).
    if (term < previous) {
      const double ratio = term / previous;
      if (term * ratio <= 1e-16 * sum * (1.0 - ratio)) break;
    } else if (term == 0.0 && m > lambda) {
      break;
    }
    previous = term;
    log_p += log_lambda - std::log(m + 1.0);
    cdf_mu += std::exp(log_q_next);
    log_q_next += log_mu - std::log(m + 2.0);
  }
  return std::clamp(sum, 0.0, 1.0);
}

double chan_relative_error_estimate(const EncounterGeometry& g, double hard_body_radius_m) {
  const double v = (g.miss_x_m * g.miss_x_m) / (g.sigma_x_m * g.sigma_x_m) +
                   (g.miss_y_m * g.miss_y_m) / (g.sigma_y_m * g.sigma_y_m);
  const double ratio = hard_body_radius_m / std::min(g.sigma_x_m, g.sigma_y_m);
  return (1.0 + v) * ratio * ratio / 8.0;
}

}  // namespace kessler::assessment
