// Mission lifecycles: an active payload keeps station (drag compensated) for its operational lifetime;
// at its end, post-mission disposal succeeds with a probability, drawn per object, and moves it to an
// orbit that decays within a target time; on failure it stays where it is, passive
// (core/traffic/README.md).
#pragma once

#include <cstdint>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "core/population/population.hpp"

namespace kessler {

class DensityTable;

struct DisposalSettings {
  double success_probability = 0.9;
  double target_lifetime_years = 25.0;  // the 25-year rule; 5 for the newer one
  bool deorbit = false;                 // success re-enters at once instead
};

// Whether object `id`'s disposal succeeds: a uniform draw keyed by (seed, id, kDisposal) below p.
bool disposal_succeeds(std::uint64_t seed, ObjectId id, double success_probability);

// The years a circular orbit at altitude_m and inclination_rad takes to decay to burn_up_altitude_m for
// an object whose drag area-to-mass (Cd A / m) is drag_m2_kg, in the table's atmosphere: the
// orbit-averaged decay da/dt = -rho(h) Cd (A / m) sqrt(mu a) f^2, integrated over altitude in 1 km
// steps, where f = 1 - omega_E a cos(i) / v is the orbit-averaged speed relative to the co-rotating
// atmosphere over the orbital speed (as the force model's drag sees it).
double circular_decay_years(double altitude_m, double inclination_rad, double drag_m2_kg,
                            double burn_up_altitude_m, const DensityTable& table);

// The circular altitude [m] whose decay time is target_years (bisection over circular_decay_years,
// to 100 m); the highest altitude searched is ceiling_m (the object's own, so disposal never raises it).
double disposal_altitude_m(double target_years, double inclination_rad, double drag_m2_kg,
                           double burn_up_altitude_m, double ceiling_m, const DensityTable& table);

// The disposal as one instantaneous change of state: a circular orbit of radius radius_m in the object's
// current orbital plane, through the direction of its current position (the transfer itself is not
// modelled). position_m and velocity_m_s are updated in place.
void move_to_circular_orbit(double radius_m, Eigen::Vector3d& position_m, Eigen::Vector3d& velocity_m_s);

}  // namespace kessler
