// Shared by the breakup tests: the reference events of tests/data/breakup/sbm_reference.json, numbers
// read from that file, and the model's densities written out again from the paper's coefficients (not
// from core/breakup/), so that a wrong coefficient in the library shows as a failed test.
#pragma once

#include <algorithm>
#include <cmath>
#include <fstream>
#include <regex>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/breakup/breakup_event.hpp"

namespace kessler::breakup_test {

inline std::string reference_json() {
  std::ifstream in(std::string(KESSLER_TEST_DATA_DIR) + "/breakup/sbm_reference.json");
  if (!in) throw std::runtime_error("cannot open tests/data/breakup/sbm_reference.json");
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// The number after "key": in the JSON object that follows "test": "<test>" (the file's objects are flat
// enough for this).
inline double reference_number(const std::string& test, const std::string& key) {
  const std::string json = reference_json();
  const std::size_t at = json.find("\"test\": \"" + test + "\"");
  if (at == std::string::npos) throw std::runtime_error("no reference test " + test);
  const std::size_t end = json.find('}', at);
  const std::size_t k = json.find("\"" + key + "\":", at);
  if (k == std::string::npos || k > end) throw std::runtime_error("no " + key + " in " + test);
  return std::stod(json.substr(json.find(':', k) + 1));
}

// The allowed deviation of the cumulative size distribution, as a fraction of the fragment count, for
// "catastrophic", "non-catastrophic" or "explosion" (the JSON's FragmentSizeDistributionTest rule).
inline double size_deviation_fraction(const std::string& which) {
  const std::string json = reference_json();
  std::smatch m;
  const std::regex re("(\\d+(\\.\\d+)?)% \\(" + which + "\\)");
  if (!std::regex_search(json, m, re)) throw std::runtime_error("no deviation for " + which);
  return std::stod(m[1].str()) / 100.0;
}

// Characteristic lengths are not in the reference (its counts do not depend on them); these are the
// sizes the tests give the parents: 560 kg spacecraft 1.5 m, 950 kg spacecraft 2 m, and the Delta
// second stage (about 6 m x 2.4 m) 3.6 m.
constexpr double kProjectileLengthM = 1.5, kTargetLengthM = 2.0, kDeltaStageLengthM = 3.6;

inline BreakupEvent reference_collision(double speed_m_s, double lc_min_m, std::uint64_t event_id) {
  BreakupEvent e;
  e.kind = BreakupKind::kCollision;
  e.min_characteristic_length_m = lc_min_m;
  e.event_id = event_id;
  e.seed = 20090210;
  const std::array<double, 3> r{7.1e6, 0.0, 0.0};
  e.parents = {
      BreakupParent{33, 560.0, kProjectileLengthM, BreakupObjectClass::kSpacecraft, r, {speed_m_s, 0.0, 0.0}},
      BreakupParent{2251, 950.0, kTargetLengthM, BreakupObjectClass::kSpacecraft, r, {0.0, 0.0, 0.0}}};
  return e;
}

inline BreakupEvent reference_explosion(double lc_min_m, std::uint64_t event_id, double scale = 1.0) {
  BreakupEvent e;
  e.kind = BreakupKind::kExplosion;
  e.min_characteristic_length_m = lc_min_m;
  e.explosion_scale = scale;
  e.event_id = event_id;
  e.seed = 19930101;
  e.parents = {BreakupParent{
      24000, 839.0, kDeltaStageLengthM, BreakupObjectClass::kRocketBody, {0.0, 7.0e6, 0.0}, {7500.0, 0, 0}}};
  return e;
}

// ---- The model's densities, from Johnson et al. (2001) and the reference JSON ----

inline double normal_cdf(double x, double mu, double sigma) {
  return 0.5 * std::erfc(-(x - mu) / (sigma * std::sqrt(2.0)));
}

// Piecewise linear in lambda: v0 for lambda <= l0, v1 for lambda >= l1, linear between.
inline double ramp(double lambda, double l0, double v0, double l1, double v1) {
  if (lambda <= l0) return v0;
  if (lambda >= l1) return v1;
  return v0 + (v1 - v0) * (lambda - l0) / (l1 - l0);
}

// CDF of chi = log10(A/m) for a fragment of size lc (m) of the given class.
inline double area_to_mass_cdf(double chi, double lc, BreakupObjectClass cls) {
  const double l = std::log10(lc);
  const double small =
      normal_cdf(chi, ramp(l, -1.75, -0.3, -1.25, -1.0), 0.2 + 0.1333 * (std::max(l, -3.5) + 3.5));
  double large;
  if (cls == BreakupObjectClass::kSpacecraft) {
    const double a = ramp(l, -1.95, 0.0, 0.55, 1.0);
    large = a * normal_cdf(chi, ramp(l, -1.1, -0.6, 0.0, -0.95), ramp(l, -1.3, 0.1, -0.3, 0.3)) +
            (1 - a) * normal_cdf(chi, ramp(l, -0.7, -1.2, -0.1, -2.0), ramp(l, -0.5, 0.5, -0.3, 0.3));
  } else {
    const double a = ramp(l, -1.4, 1.0, 0.0, 0.5);
    large = a * normal_cdf(chi, ramp(l, -0.5, -0.45, 0.0, -0.9), 0.55) +
            (1 - a) * normal_cdf(chi, -0.9, ramp(l, -1.0, 0.28, 0.1, 0.1));
  }
  const double w = lc <= 0.08 ? 0.0 : (lc >= 0.11 ? 1.0 : (lc - 0.08) / 0.03);
  return (1 - w) * small + w * large;
}

// CDF of log10(dv [m/s]) given chi.
inline double ejection_speed_cdf(double log_dv, double chi, BreakupKind kind) {
  const double mu = kind == BreakupKind::kExplosion ? 0.2 * chi + 1.85 : 0.9 * chi + 2.9;
  return normal_cdf(log_dv, mu, 0.4);
}

// Kolmogorov-Smirnov statistic of values that should be uniform on (0, 1).
inline double ks_uniform(std::vector<double> u) {
  std::sort(u.begin(), u.end());
  const double n = static_cast<double>(u.size());
  double d = 0.0;
  for (std::size_t i = 0; i < u.size(); ++i)
    d = std::max({d, static_cast<double>(i + 1) / n - u[i], u[i] - static_cast<double>(i) / n});
  return d;
}

// The KS critical value at significance 0.001 (asymptotic: 1.949 / sqrt(n)).
inline double ks_critical(std::size_t n) {
  return 1.949 / std::sqrt(static_cast<double>(n));
}

}  // namespace kessler::breakup_test
