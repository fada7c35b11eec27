// Each gravity term against the central-difference gradient of its potential, the potential written
// here from the spherical-harmonic expansion (geocentric latitude and longitude, normalised Legendre
// functions), not from the Cartesian formulas the force model uses.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <numbers>
#include <random>

#include "core/physics/constants.hpp"
#include "core/physics/force_model.hpp"
#include "core/physics/gravity.hpp"

namespace kessler {
namespace {

constexpr double kMu = constants::kEarthMu_m3_s2;
constexpr double kR = constants::kEarthGravityRadius_m;

// U = mu/r (R/r)^l Pbar_lm(sin phi) (Cbar cos m lambda + Sbar sin m lambda), lambda from Greenwich.
double harmonic_potential(const Eigen::Vector3d& r_inertial, double theta, int l, int m) {
  const double x = std::cos(theta) * r_inertial.x() + std::sin(theta) * r_inertial.y();
  const double y = -std::sin(theta) * r_inertial.x() + std::cos(theta) * r_inertial.y();
  const double rn = r_inertial.norm();
  const double sin_phi = r_inertial.z() / rn;
  const double lambda = std::atan2(y, x);
  if (l == 2 && m == 0) {
    const double p20 = std::sqrt(5.0) * 0.5 * (3.0 * sin_phi * sin_phi - 1.0);
    return kMu / rn * std::pow(kR / rn, 2) * p20 * constants::kC20Normalised;
  }
  const double p22 = std::sqrt(5.0 / 12.0) * 3.0 * (1.0 - sin_phi * sin_phi);
  return kMu / rn * std::pow(kR / rn, 2) * p22 *
         (constants::kC22Normalised * std::cos(2 * lambda) +
          constants::kS22Normalised * std::sin(2 * lambda));
}

Eigen::Vector3d central_gradient(const std::function<double(const Eigen::Vector3d&)>& u,
                                 const Eigen::Vector3d& r, double h) {
  Eigen::Vector3d g;
  for (int k = 0; k < 3; ++k) {
    Eigen::Vector3d plus = r, minus = r;
    plus[k] += h;
    minus[k] -= h;
    g[k] = (u(plus) - u(minus)) / (2 * h);
  }
  return g;
}

struct Sample {
  Eigen::Vector3d r;
  double theta;
};

std::vector<Sample> samples() {
  std::mt19937_64 rng(20220301);
  std::uniform_real_distribution<double> radius(6500e3, 8500e3), unit(-1.0, 1.0),
      angle(0, 2 * std::numbers::pi);
  std::vector<Sample> out;
  while (out.size() < 200) {
    Eigen::Vector3d d(unit(rng), unit(rng), unit(rng));
    if (d.norm() < 0.1 || d.norm() > 1) continue;
    out.push_back({d.normalized() * radius(rng), angle(rng)});
  }
  return out;
}

double relative_error(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return (a - b).norm() / b.norm();
}

TEST(Gravity, KeplerIsTheGradientOfMuOverR) {
  for (const auto& s : samples()) {
    auto u = [](const Eigen::Vector3d& r) { return kMu / r.norm(); };
    EXPECT_LT(relative_error(gravity::kepler_acceleration(s.r), central_gradient(u, s.r, 1.0)), 1e-6);
  }
}

TEST(Gravity, J2IsTheGradientOfTheZonalPotential) {
  for (const auto& s : samples()) {
    auto u = [&](const Eigen::Vector3d& r) { return harmonic_potential(r, s.theta, 2, 0); };
    EXPECT_LT(relative_error(gravity::j2_acceleration(s.r), central_gradient(u, s.r, 1.0)), 1e-6);
    // The force model's own potential agrees with the expansion.
    EXPECT_NEAR(gravity::j2_potential(s.r), u(s.r), 1e-10 * std::abs(u(s.r)));
  }
}

TEST(Gravity, C22S22IsTheGradientOfTheSectorialPotentialInTheRotatingFrame) {
  for (const auto& s : samples()) {
    auto u = [&](const Eigen::Vector3d& r) { return harmonic_potential(r, s.theta, 2, 2); };
    EXPECT_LT(relative_error(gravity::c22_s22_acceleration(s.r, s.theta), central_gradient(u, s.r, 1.0)),
              1e-6);
    EXPECT_NEAR(gravity::c22_s22_potential(s.r, s.theta), u(s.r), 1e-10 * std::abs(u(s.r)));
  }
}

TEST(Gravity, UnnormalisedCoefficientsMatchPublishedValues) {
  // EGM96 unnormalised: J2 = 1.08262668355e-3, C22 = 1.57446037456e-6, S22 = -9.03803806639e-7.
  EXPECT_NEAR(gravity::kJ2, 1.08262668355e-3, 1e-13);
  EXPECT_NEAR(gravity::kC22, 1.57446037456e-6, 1e-16);
  EXPECT_NEAR(gravity::kS22, -9.03803806639e-7, 1e-16);
}

TEST(Gravity, ForceModelSumsTheSwitchedTerms) {
  ForceModelSettings only_gravity;
  only_gravity.drag = only_gravity.srp = false;
  const UtcEpoch epoch = UtcEpoch::from_calendar(2022, 3, 1, 0, 0, 0);
  ForceModel model(only_gravity, epoch);
  const double t = 1234.5;
  const double theta = epoch.gmst_rad() + constants::kEarthRotationRate_rad_s * t;
  for (const auto& s : samples()) {
    const Eigen::Vector3d expected = gravity::kepler_acceleration(s.r) + gravity::j2_acceleration(s.r) +
                                     gravity::c22_s22_acceleration(s.r, theta);
    EXPECT_LT(relative_error(model.acceleration(s.r, Eigen::Vector3d(0, 7.5e3, 0), t, {}), expected), 1e-14);
  }
}

}  // namespace
}  // namespace kessler
