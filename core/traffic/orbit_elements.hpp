// Classical orbital elements and the two-body state they give, for placing launched objects. Frame:
// the core's inertial frame (TEME of the scenario epoch, core/population/population.hpp): the equator
// and the x axis of the epoch. Units: m, m/s, radians.
#pragma once

#include <Eigen/Core>

namespace kessler {

struct OrbitElements {
  double semi_major_axis_m = 0.0;
  double eccentricity = 0.0;             // [0, 1)
  double inclination_rad = 0.0;          // [0, pi]
  double raan_rad = 0.0;                 // right ascension of the ascending node
  double argument_of_perigee_rad = 0.0;  //
  double mean_anomaly_rad = 0.0;
};

// Perigee and apogee altitudes above the equatorial radius [m] as a, e.
OrbitElements elements_from_altitudes(double perigee_altitude_m, double apogee_altitude_m,
                                      double inclination_rad);

// The eccentric anomaly E of mean anomaly M (Kepler's equation M = E - e sin E), by Newton's method
// from E = M (e < 0.8) or pi, to machine precision.
double eccentric_anomaly(double mean_anomaly_rad, double eccentricity);

// Position [m] and velocity [m/s] of the elements in two-body motion.
void state_from_elements(const OrbitElements& el, Eigen::Vector3d& position_m, Eigen::Vector3d& velocity_m_s);

// The elements advanced by dt_s of two-body motion (the mean anomaly alone moves).
OrbitElements advance(const OrbitElements& el, double dt_s);

}  // namespace kessler
