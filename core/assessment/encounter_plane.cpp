#include "core/assessment/encounter_plane.hpp"

#include <cmath>

#include <Eigen/Geometry>

namespace kessler::assessment {

Eigen::Matrix3d rtn_to_inertial(const Eigen::Vector3d& r_m, const Eigen::Vector3d& v_m_s) {
  const Eigen::Vector3d radial = r_m.normalized();
  const Eigen::Vector3d normal = r_m.cross(v_m_s).normalized();
  const Eigen::Vector3d transverse = normal.cross(radial);
  Eigen::Matrix3d m;
  m.col(0) = radial;
  m.col(1) = transverse;
  m.col(2) = normal;
  return m;
}

namespace {

// Any unit vector normal to u (u a unit vector).
Eigen::Vector3d any_normal(const Eigen::Vector3d& u) {
  const Eigen::Vector3d axis = std::abs(u.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  return u.cross(axis).normalized();
}

}  // namespace

bool project_to_encounter_plane(const Eigen::Vector3d& relative_position_m,
                                const Eigen::Vector3d& relative_velocity_m_s,
                                const Eigen::Matrix3d& combined_covariance_m2, EncounterGeometry& out) {
  const double speed = relative_velocity_m_s.norm();
  if (!(speed > 0.0) || !std::isfinite(speed)) return false;
  const Eigen::Vector3d along = relative_velocity_m_s / speed;
  // At TCA the miss is normal to the relative velocity; drop any residual along it.
  const Eigen::Vector3d miss = relative_position_m - relative_position_m.dot(along) * along;
  const double miss_m = miss.norm();
  const Eigen::Vector3d e1 = miss_m > 0.0 ? Eigen::Vector3d(miss / miss_m) : any_normal(along);
  const Eigen::Vector3d e2 = along.cross(e1);
  Eigen::Matrix<double, 2, 3> plane;
  plane.row(0) = e1.transpose();
  plane.row(1) = e2.transpose();
  const Eigen::Matrix2d c2 = plane * combined_covariance_m2 * plane.transpose();
  // Principal axes of the 2x2 covariance, closed form.
  const double a = c2(0, 0);
  const double b = 0.5 * (c2(0, 1) + c2(1, 0));
  const double d = c2(1, 1);
  const double mean = 0.5 * (a + d);
  const double half_diff = 0.5 * (a - d);
  const double radius = std::hypot(half_diff, b);
  const double major = mean + radius;
  const double minor = mean - radius;
  if (!(minor > 0.0) || !std::isfinite(major)) return false;
  // Angle of the major axis from e1; the miss is (miss_m, 0) in (e1, e2).
  const double angle = 0.5 * std::atan2(2.0 * b, a - d);
  out.sigma_x_m = std::sqrt(major);
  out.sigma_y_m = std::sqrt(minor);
  out.miss_x_m = miss_m * std::cos(angle);
  out.miss_y_m = -miss_m * std::sin(angle);
  return true;
}

double encounter_duration_s(const Eigen::Vector3d& relative_velocity_m_s,
                            const Eigen::Matrix3d& combined_covariance_m2) {
  const double speed = relative_velocity_m_s.norm();
  if (!(speed > 0.0)) return INFINITY;
  const Eigen::Vector3d along = relative_velocity_m_s / speed;
  const double sigma_along_m = std::sqrt(std::max(0.0, along.dot(combined_covariance_m2 * along)));
  return 10.0 * sigma_along_m / speed;
}

}  // namespace kessler::assessment
