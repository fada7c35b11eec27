// The Earth's gravity field as the paper models it: the central term (Kepler), the zonal J2 term and the
// sectorial C22/S22 terms, each as an acceleration and as its potential (a = grad U).
//
// Sources: Vallado, "Fundamentals of Astrodynamics and Applications", sec. 8.6 (the geopotential and its
// Cartesian partials); coefficients are EGM96 normalised values (constants.hpp), unnormalised with
// N_lm = sqrt((2 - delta_m0)(2l + 1)(l - m)!/(l + m)!) (Vallado eq. 8-22):
//   J2 = -sqrt(5) C20_bar,  C22 = sqrt(5/12) C22_bar,  S22 = sqrt(5/12) S22_bar.
// Potentials (r = |x|, Earth-fixed x_e, y_e for the sectorial term):
//   U_kepler = mu / r
//   U_J2     = -mu J2 R^2 (3 z^2/r^2 - 1) / (2 r^3)
//   U_22     = 3 mu R^2 (C22 (x_e^2 - y_e^2) + 2 S22 x_e y_e) / r^5
// The sectorial term lives in the Earth-fixed frame, rotated from TEME by theta (earth_rotation.hpp).
//
// The inline functions take plain doubles so the propagator's batched loop can inline and vectorise them.
#pragma once

#include <cmath>

#include <Eigen/Core>

#include "core/physics/constants.hpp"

namespace kessler::gravity {

inline constexpr double kJ2 = -2.2360679774997896964 * constants::kC20Normalised;   // sqrt(5) = 2.236...
inline constexpr double kC22 = 0.64549722436790281419 * constants::kC22Normalised;  // sqrt(5/12)
inline constexpr double kS22 = 0.64549722436790281419 * constants::kS22Normalised;

// Central term: a = -mu x / r^3. inv_r = 1/r is passed in because every term needs it.
[[gnu::always_inline]] inline void kepler_acceleration(double mu_m3_s2, double x, double y, double z,
                                                       double inv_r, double& ax, double& ay, double& az) {
  const double f = -mu_m3_s2 * inv_r * inv_r * inv_r;
  ax = f * x;
  ay = f * y;
  az = f * z;
}

// J2: a = -(3/2) J2 mu R^2 / r^5 (x (1 - 5 z^2/r^2), y (1 - 5 z^2/r^2), z (3 - 5 z^2/r^2)).
// j2_mu_r2 = J2 mu R^2 (zero switches the term off).
[[gnu::always_inline]] inline void j2_acceleration(double j2_mu_r2, double x, double y, double z,
                                                   double inv_r, double& ax, double& ay, double& az) {
  const double inv_r2 = inv_r * inv_r;
  const double f = -1.5 * j2_mu_r2 * inv_r2 * inv_r2 * inv_r;
  const double z2_r2 = 5.0 * z * z * inv_r2;
  ax = f * x * (1.0 - z2_r2);
  ay = f * y * (1.0 - z2_r2);
  az = f * z * (3.0 - z2_r2);
}

// C22/S22, gradient of U_22 in the Earth-fixed frame, rotated back to TEME. c22_mu_r2 = C22 mu R^2,
// s22_mu_r2 = S22 mu R^2; cos_theta, sin_theta of the Earth's rotation angle.
[[gnu::always_inline]] inline void c22_s22_acceleration(double c22_mu_r2, double s22_mu_r2, double cos_theta,
                                                        double sin_theta, double x, double y, double z,
                                                        double inv_r, double& ax, double& ay, double& az) {
  const double xe = cos_theta * x + sin_theta * y;
  const double ye = -sin_theta * x + cos_theta * y;
  const double inv_r2 = inv_r * inv_r;
  const double k = 3.0 * inv_r2 * inv_r2 * inv_r;  // 3 / r^5
  const double q = c22_mu_r2 * (xe * xe - ye * ye) + 2.0 * s22_mu_r2 * xe * ye;
  const double radial = 5.0 * q * inv_r2;
  const double aex = k * (2.0 * c22_mu_r2 * xe + 2.0 * s22_mu_r2 * ye - radial * xe);
  const double aey = k * (-2.0 * c22_mu_r2 * ye + 2.0 * s22_mu_r2 * xe - radial * ye);
  az = k * (-radial * z);
  ax = cos_theta * aex - sin_theta * aey;
  ay = sin_theta * aex + cos_theta * aey;
}

// Potentials [m^2/s^2] and Eigen conveniences, for tests and tools.
double kepler_potential(const Eigen::Vector3d& r_m);
double j2_potential(const Eigen::Vector3d& r_m);
double c22_s22_potential(const Eigen::Vector3d& r_m, double earth_angle_rad);
Eigen::Vector3d kepler_acceleration(const Eigen::Vector3d& r_m);
Eigen::Vector3d j2_acceleration(const Eigen::Vector3d& r_m);
Eigen::Vector3d c22_s22_acceleration(const Eigen::Vector3d& r_m, double earth_angle_rad);

}  // namespace kessler::gravity
