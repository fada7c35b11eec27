// Test helpers: the analytic two-body solution (Kepler's equation with Lagrange f and g functions,
// Vallado sec. 2.3) and orbital-element conversions, written independently of the propagator.
#pragma once

#include <cmath>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "core/physics/constants.hpp"

namespace kessler::testing {

inline constexpr double kMu = constants::kEarthMu_m3_s2;

// State of an elliptic orbit from a, e, i, RAAN, argument of perigee, true anomaly (radians, metres).
inline void state_from_elements(double a, double e, double inc, double raan, double argp, double nu,
                                Eigen::Vector3d& r, Eigen::Vector3d& v) {
  const double p = a * (1 - e * e);
  const double rn = p / (1 + e * std::cos(nu));
  const Eigen::Vector3d r_pf(rn * std::cos(nu), rn * std::sin(nu), 0);
  const Eigen::Vector3d v_pf(-std::sqrt(kMu / p) * std::sin(nu), std::sqrt(kMu / p) * (e + std::cos(nu)), 0);
  const double cO = std::cos(raan), sO = std::sin(raan), ci = std::cos(inc), si = std::sin(inc);
  const double cw = std::cos(argp), sw = std::sin(argp);
  Eigen::Matrix3d q;
  q << cO * cw - sO * sw * ci, -cO * sw - sO * cw * ci, sO * si,  //
      sO * cw + cO * sw * ci, -sO * sw + cO * cw * ci, -cO * si,  //
      sw * si, cw * si, ci;
  r = q * r_pf;
  v = q * v_pf;
}

// Position after dt seconds of pure Kepler motion from (r0, v0), elliptic orbits.
inline Eigen::Vector3d kepler_position(const Eigen::Vector3d& r0, const Eigen::Vector3d& v0, double dt) {
  const double r0n = r0.norm();
  const double a = 1.0 / (2.0 / r0n - v0.squaredNorm() / kMu);
  const double n = std::sqrt(kMu / (a * a * a));
  const double e_cos = 1.0 - r0n / a;
  const double e_sin = r0.dot(v0) / std::sqrt(kMu * a);
  const double e = std::hypot(e_cos, e_sin);
  const double e0 = std::atan2(e_sin, e_cos);
  const double m = (e0 - e_sin) + n * dt;
  double ecc_anomaly = m;
  for (int k = 0; k < 50; ++k) {
    const double delta = (ecc_anomaly - e * std::sin(ecc_anomaly) - m) / (1.0 - e * std::cos(ecc_anomaly));
    ecc_anomaly -= delta;
    if (std::abs(delta) < 1e-15) break;
  }
  const double de = ecc_anomaly - e0;
  const double f = 1.0 - a / r0n * (1.0 - std::cos(de));
  const double g = dt - (de - std::sin(de)) / n;
  return f * r0 + g * v0;
}

}  // namespace kessler::testing
