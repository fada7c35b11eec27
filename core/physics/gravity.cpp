#include "core/physics/gravity.hpp"

namespace kessler::gravity {
namespace {
constexpr double kMu = constants::kEarthMu_m3_s2;
constexpr double kR2 = constants::kEarthGravityRadius_m * constants::kEarthGravityRadius_m;
}  // namespace

double kepler_potential(const Eigen::Vector3d& r) {
  return kMu / r.norm();
}

double j2_potential(const Eigen::Vector3d& r) {
  const double rn = r.norm();
  return -kMu * kJ2 * kR2 * (3.0 * r.z() * r.z() / (rn * rn) - 1.0) / (2.0 * rn * rn * rn);
}

double c22_s22_potential(const Eigen::Vector3d& r, double theta) {
  const double xe = std::cos(theta) * r.x() + std::sin(theta) * r.y();
  const double ye = -std::sin(theta) * r.x() + std::cos(theta) * r.y();
  const double rn = r.norm();
  return 3.0 * kMu * kR2 * (kC22 * (xe * xe - ye * ye) + 2.0 * kS22 * xe * ye) / std::pow(rn, 5);
}

Eigen::Vector3d kepler_acceleration(const Eigen::Vector3d& r) {
  Eigen::Vector3d a;
  kepler_acceleration(kMu, r.x(), r.y(), r.z(), 1.0 / std::sqrt(r.squaredNorm()), a.x(), a.y(), a.z());
  return a;
}

Eigen::Vector3d j2_acceleration(const Eigen::Vector3d& r) {
  Eigen::Vector3d a;
  j2_acceleration(kJ2 * kMu * kR2, r.x(), r.y(), r.z(), 1.0 / std::sqrt(r.squaredNorm()), a.x(), a.y(),
                  a.z());
  return a;
}

Eigen::Vector3d c22_s22_acceleration(const Eigen::Vector3d& r, double theta) {
  Eigen::Vector3d a;
  c22_s22_acceleration(kC22 * kMu * kR2, kS22 * kMu * kR2, std::cos(theta), std::sin(theta), r.x(), r.y(),
                       r.z(), 1.0 / std::sqrt(r.squaredNorm()), a.x(), a.y(), a.z());
  return a;
}

}  // namespace kessler::gravity
