#include "core/assessment/pc_foster.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <vector>

namespace kessler::assessment {

namespace {

// QUADPACK's 15-point Kronrod rule and its embedded 7-point Gauss rule (nodes on [0, 1], symmetric).
constexpr std::array<double, 8> kKronrodNodes = {
    0.991455371120812639206854697526329, 0.949107912342758524526189684047851,
    0.864864423359769072789712788640926, 0.741531185599394439863864773280788,
    0.586087235467691130294144845693013, 0.405845151377397166906606412076961,
    0.207784955007898467600689403773245, 0.0};
constexpr std::array<double, 8> kKronrodWeights = {
    0.022935322010529224963732008058970, 0.063092092629978553290700663189204,
    0.104790010322250183839876322541518, 0.140653259715525918745189590510238,
    0.169004726639267902826583426598550, 0.190350578064785409913256402421014,
    0.204432940075298892414161999234649, 0.209482141084727828012999174891714};
// Gauss weights for Kronrod nodes 1, 3, 5, 7.
constexpr std::array<double, 4> kGaussWeights = {
    0.129484966168869693270611432679082, 0.279705391489276667901467771423780,
    0.381830050505118944950369775488975, 0.417959183673469387755102040816327};

// P(-h <= B <= h) for B ~ N(mean, sigma^2), accurate in the tails (erfc on the far side).
double interval_probability(double h, double mean, double sigma) {
  const double scale = 1.0 / (std::numbers::sqrt2 * sigma);
  const double lo = (-h - mean) * scale;
  const double hi = (h - mean) * scale;
  if (lo >= 0.0) return 0.5 * (std::erfc(lo) - std::erfc(hi));
  if (hi <= 0.0) return 0.5 * (std::erfc(-hi) - std::erfc(-lo));
  return 1.0 - 0.5 * (std::erfc(hi) + std::erfc(-lo));
}

struct DiskIntegrand {
  double radius, mean_a, sigma_a, mean_b, sigma_b;
  // theta in [-pi/2, pi/2]: t = R sin(theta) along axis a, the chord half-length R cos(theta) along b.
  double operator()(double theta) const {
    const double c = std::cos(theta);
    const double t = radius * std::sin(theta);
    const double z = (t - mean_a) / sigma_a;
    const double density = std::exp(-0.5 * z * z) / (std::sqrt(2.0 * std::numbers::pi) * sigma_a);
    return radius * c * density * interval_probability(radius * c, mean_b, sigma_b);
  }
};

struct Estimate {
  double value, error;
};

Estimate gauss_kronrod(const DiskIntegrand& f, double lo, double hi) {
  const double centre = 0.5 * (lo + hi);
  const double half = 0.5 * (hi - lo);
  double kronrod = kKronrodWeights[7] * f(centre);
  double gauss = kGaussWeights[3] * f(centre);
  for (std::size_t i = 0; i < 7; ++i) {
    const double sum = f(centre - half * kKronrodNodes[i]) + f(centre + half * kKronrodNodes[i]);
    kronrod += kKronrodWeights[i] * sum;
    if (i % 2 == 1) gauss += kGaussWeights[i / 2] * sum;
  }
  return {kronrod * half, std::abs(kronrod - gauss) * half};
}

double adaptive(const DiskIntegrand& f, double lo, double hi, double tolerance, int depth) {
  const Estimate whole = gauss_kronrod(f, lo, hi);
  if (whole.error <= tolerance || depth >= 40) return whole.value;
  const double mid = 0.5 * (lo + hi);
  return adaptive(f, lo, mid, 0.5 * tolerance, depth + 1) + adaptive(f, mid, hi, 0.5 * tolerance, depth + 1);
}

}  // namespace

double pc_foster(const EncounterGeometry& g, double hard_body_radius_m) {
  if (!(hard_body_radius_m > 0.0)) return 0.0;
  // Numerical axis a: the larger sigma (smooth integrand); closed-form axis b: the smaller.
  const bool x_is_larger = g.sigma_x_m >= g.sigma_y_m;
  const DiskIntegrand f{hard_body_radius_m, x_is_larger ? g.miss_x_m : g.miss_y_m,
                        x_is_larger ? g.sigma_x_m : g.sigma_y_m, x_is_larger ? g.miss_y_m : g.miss_x_m,
                        x_is_larger ? g.sigma_y_m : g.sigma_x_m};
  // Break points where the density along a peaks and falls off, so no narrow peak is stepped over.
  std::vector<double> breaks = {-std::numbers::pi / 2, std::numbers::pi / 2};
  for (const double k : {-8.0, -4.0, -2.0, -1.0, 0.0, 1.0, 2.0, 4.0, 8.0}) {
    const double s = (f.mean_a + k * f.sigma_a) / f.radius;
    if (s > -1.0 && s < 1.0) breaks.push_back(std::asin(s));
  }
  std::sort(breaks.begin(), breaks.end());
  breaks.erase(std::unique(breaks.begin(), breaks.end()), breaks.end());
  double coarse = 0.0;
  for (std::size_t i = 0; i + 1 < breaks.size(); ++i)
    coarse += gauss_kronrod(f, breaks[i], breaks[i + 1]).value;
  const double tolerance = std::max(1e-12 * std::abs(coarse), 1e-300) / static_cast<double>(breaks.size());
  double total = 0.0;
  for (std::size_t i = 0; i + 1 < breaks.size(); ++i)
    total += adaptive(f, breaks[i], breaks[i + 1], tolerance, 0);
  return std::clamp(total, 0.0, 1.0);
}

}  // namespace kessler::assessment
