// Ejection speed and direction: log10(dv [m/s]) ~ N(mu(chi), 0.4) with chi = log10(A/m), and an
// isotropic direction.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>

#include "core/breakup/breakup_event.hpp"

namespace kessler {

constexpr double kLogEjectionSpeedSigma = 0.4;

// mu = 0.2 chi + 1.85 (explosion), 0.9 chi + 2.9 (collision).
inline double mean_log_ejection_speed(BreakupKind kind, double chi) {
  return kind == BreakupKind::kExplosion ? 0.2 * chi + 1.85 : 0.9 * chi + 2.9;
}

// Unit vector uniform on the sphere from two uniforms in (0, 1): cos(theta) = 2 u1 - 1, phi = 2 pi u2.
inline std::array<double, 3> isotropic_direction(double u1, double u2) {
  const double c = 2.0 * u1 - 1.0;
  const double s = std::sqrt(std::max(0.0, 1.0 - c * c));
  const double phi = 2.0 * 3.14159265358979323846 * u2;
  return {s * std::cos(phi), s * std::sin(phi), c};
}

}  // namespace kessler
