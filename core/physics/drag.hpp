// Atmospheric drag with an atmosphere co-rotating with the Earth (Vallado sec. 8.6.2, eq. 8-29):
//   a = -1/2 rho(h) (Cd A/m) |v_rel| v_rel,   v_rel = v - omega_E x r,   omega_E = (0, 0, omega_E) in TEME.
#pragma once

#include <cmath>

#include "core/physics/constants.hpp"

namespace kessler {

// rho [kg/m^3] at the object's altitude; drag_area_to_mass = Cd A/m [m^2/kg].
[[gnu::always_inline]] inline void drag_acceleration(double rho_kg_m3, double drag_area_to_mass_m2_kg,
                                                     double x, double y, double vx, double vy, double vz,
                                                     double& ax, double& ay, double& az) {
  constexpr double w = constants::kEarthRotationRate_rad_s;
  const double vrx = vx + w * y;
  const double vry = vy - w * x;
  const double vrz = vz;
  const double speed = std::sqrt(vrx * vrx + vry * vry + vrz * vrz);
  const double f = -0.5 * rho_kg_m3 * drag_area_to_mass_m2_kg * speed;
  ax = f * vrx;
  ay = f * vry;
  az = f * vrz;
}

}  // namespace kessler
