// Exact two-body (Kepler) motion for tests and the benchmark: propagates a state by any time with
// universal variables, so tests of conjunction detection do not depend on the numerical propagator.
#pragma once

#include <cmath>
#include <random>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "core/physics/constants.hpp"
#include "core/population/population.hpp"

namespace kessler::testing {

struct KeplerState {
  Eigen::Vector3d r_m;    // inertial, m
  Eigen::Vector3d v_m_s;  // inertial, m/s
};

// Stumpff functions C(z) and S(z).
inline void stumpff(double z, double& c, double& s) {
  if (z > 1e-6) {
    const double q = std::sqrt(z);
    c = (1.0 - std::cos(q)) / z;
    s = (q - std::sin(q)) / (q * q * q);
  } else if (z < -1e-6) {
    const double q = std::sqrt(-z);
    c = (std::cosh(q) - 1.0) / (-z);
    s = (std::sinh(q) - q) / (q * q * q);
  } else {
    c = 1.0 / 2.0 - z / 24.0 + z * z / 720.0 - z * z * z / 40320.0;
    s = 1.0 / 6.0 - z / 120.0 + z * z / 5040.0 - z * z * z / 362880.0;
  }
}

// The state after dt_s of two-body motion about the Earth (mu of the force model).
inline KeplerState kepler_propagate(const KeplerState& s0, double dt_s,
                                    double mu = constants::kEarthMu_m3_s2) {
  if (dt_s == 0.0) return s0;
  const double sqrt_mu = std::sqrt(mu);
  const double r0 = s0.r_m.norm();
  const double vr0 = s0.r_m.dot(s0.v_m_s) / r0;
  const double alpha = 2.0 / r0 - s0.v_m_s.squaredNorm() / mu;  // 1 / a
  double chi = sqrt_mu * std::fabs(alpha) * dt_s;               // universal anomaly, first guess
  if (alpha <= 0.0) chi = sqrt_mu * dt_s / r0;
  double c = 0.5, s = 1.0 / 6.0;
  for (int iteration = 0; iteration < 60; ++iteration) {
    const double z = alpha * chi * chi;
    stumpff(z, c, s);
    const double chi2 = chi * chi, chi3 = chi2 * chi;
    const double f =
        r0 * vr0 / sqrt_mu * chi2 * c + (1.0 - alpha * r0) * chi3 * s + r0 * chi - sqrt_mu * dt_s;
    const double df = r0 * vr0 / sqrt_mu * chi * (1.0 - z * s) + (1.0 - alpha * r0) * chi2 * c + r0;
    const double step = f / df;
    chi -= step;
    if (std::fabs(step) <= 1e-15 * std::fabs(chi) + 1e-300) break;
  }
  const double z = alpha * chi * chi;
  stumpff(z, c, s);
  const double chi2 = chi * chi, chi3 = chi2 * chi;
  const double f = 1.0 - chi2 / r0 * c;
  const double g = dt_s - chi3 * s / sqrt_mu;
  KeplerState out;
  out.r_m = f * s0.r_m + g * s0.v_m_s;
  const double r = out.r_m.norm();
  const double fdot = sqrt_mu / (r * r0) * (z * chi * s - chi);
  const double gdot = 1.0 - chi2 / r * c;
  out.v_m_s = fdot * s0.r_m + gdot * s0.v_m_s;
  return out;
}

// Classical elements to a state (mean anomaly solved for the eccentric anomaly).
inline KeplerState state_from_elements(double a_m, double e, double i_rad, double raan_rad, double argp_rad,
                                       double mean_anomaly_rad, double mu = constants::kEarthMu_m3_s2) {
  double ecc_anomaly = mean_anomaly_rad;
  for (int k = 0; k < 50; ++k)
    ecc_anomaly -=
        (ecc_anomaly - e * std::sin(ecc_anomaly) - mean_anomaly_rad) / (1.0 - e * std::cos(ecc_anomaly));
  const double cos_e = std::cos(ecc_anomaly), sin_e = std::sin(ecc_anomaly);
  const double b = a_m * std::sqrt(1.0 - e * e);
  const Eigen::Vector3d r_pf(a_m * (cos_e - e), b * sin_e, 0.0);
  const double rn = a_m * (1.0 - e * cos_e);
  const double n = std::sqrt(mu / (a_m * a_m * a_m));
  const Eigen::Vector3d v_pf(-a_m * a_m * n / rn * sin_e, a_m * b * n / rn * cos_e, 0.0);
  const Eigen::Matrix3d rot = (Eigen::AngleAxisd(raan_rad, Eigen::Vector3d::UnitZ()) *
                               Eigen::AngleAxisd(i_rad, Eigen::Vector3d::UnitX()) *
                               Eigen::AngleAxisd(argp_rad, Eigen::Vector3d::UnitZ()))
                                  .toRotationMatrix();
  return KeplerState{rot * r_pf, rot * v_pf};
}

// A random LEO population: near-circular orbits with altitudes in [alt_lo, alt_hi], random planes;
// radii drawn from [radius_lo, radius_hi]; every fifth object active. Ids 1000 + 7 k (not contiguous).
inline std::vector<KeplerState> random_leo_states(std::size_t n, std::uint64_t seed, double alt_lo_m,
                                                  double alt_hi_m) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<KeplerState> states;
  states.reserve(n);
  const double two_pi = 2.0 * M_PI;
  for (std::size_t k = 0; k < n; ++k) {
    const double alt = alt_lo_m + (alt_hi_m - alt_lo_m) * u(rng);
    const double e = 0.01 * u(rng);
    const double a = (constants::kEarthEquatorialRadius_m + alt) / (1.0 - e);  // perigee at alt
    const double inc = std::acos(1.0 - 2.0 * u(rng));
    states.push_back(state_from_elements(a, e, inc, two_pi * u(rng), two_pi * u(rng), two_pi * u(rng)));
  }
  return states;
}

inline Population population_from_states(const std::vector<KeplerState>& states,
                                         const std::vector<double>& radii,
                                         const std::vector<ObjectStatus>& statuses,
                                         const std::vector<ObjectId>& ids) {
  Population p;
  p.reserve(states.size());
  for (std::size_t k = 0; k < states.size(); ++k) {
    ObjectRecord rec;
    rec.id = ids[k];
    rec.name = "T" + std::to_string(ids[k]);
    rec.position_m = states[k].r_m;
    rec.velocity_m_s = states[k].v_m_s;
    rec.radius_m = radii[k];
    rec.mass_kg = 100.0;
    rec.status = statuses[k];
    p.add(rec);
  }
  return p;
}

}  // namespace kessler::testing
