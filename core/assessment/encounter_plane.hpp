// The short-encounter geometry: the combined position covariance of two objects at the time of closest
// approach (TCA) projected onto the encounter plane (the plane normal to their relative velocity), in
// the principal axes of the projected covariance.
#pragma once

#include <Eigen/Core>

namespace kessler::assessment {

// The miss vector and the 1-sigma extents of the combined covariance in the encounter plane, along the
// covariance's principal axes (x: the larger sigma). Metres.
struct EncounterGeometry {
  double miss_x_m = 0.0;
  double miss_y_m = 0.0;
  double sigma_x_m = 0.0;
  double sigma_y_m = 0.0;
};

// Rotation from an object's RTN frame (radial, transverse, normal) to the inertial frame of its state:
// columns R, T, N. RTN covariances (CDMs, the covariance model) turn inertial as M C M^T.
Eigen::Matrix3d rtn_to_inertial(const Eigen::Vector3d& r_m, const Eigen::Vector3d& v_m_s);

// Projects the combined position covariance (inertial, m^2) onto the plane normal to the relative
// velocity v2 - v1, with the relative position r2 - r1. Fails (returns false) when the relative velocity
// is zero or the projected covariance is not positive definite.
bool project_to_encounter_plane(const Eigen::Vector3d& relative_position_m,
                                const Eigen::Vector3d& relative_velocity_m_s,
                                const Eigen::Matrix3d& combined_covariance_m2, EncounterGeometry& out);

// The 2-D short-encounter assumption: the encounter (the time the relative motion takes to cross
// +-5 sigma of the combined covariance along the relative velocity) is short against the time over
// which relative motion curves. Returns that encounter duration in seconds.
double encounter_duration_s(const Eigen::Vector3d& relative_velocity_m_s,
                            const Eigen::Matrix3d& combined_covariance_m2);

}  // namespace kessler::assessment
