// Atmospheric drag with an atmosphere co-rotating with the Earth (Vallado sec. 8.6.2, eq. 8-29):
//   a = -1/2 rho(h) (Cd A/m) |v_rel| v_rel,   v_rel = v - omega_E x r,   omega_E = (0, 0, omega_E) in TEME.
// The factor k = 1/2 rho (Cd A/m) |v_rel| [1/s] is capped at rate_limit_per_s: an explicit integrator
// with step dt is unstable once k dt approaches 1, which only happens deep in the atmosphere (below about
// 100 km for Cd A/m = 1 and dt = 10 s), where objects have burnt up already. The cap keeps such states
// bounded instead of exploding; above it the formula is exact (the default limit is infinite).
//
// drag_flow() is drag alone over a time h at a fixed position, solved exactly: the propagator's kicks
// use it (half before and half after the velocity-independent kick) so that each kick, and hence the
// whole Yoshida step, stays time-symmetric with drag (symplectic_propagator.hpp).
#pragma once

#include <cmath>

#include "core/physics/constants.hpp"

namespace kessler {

// rho [kg/m^3] at the object's altitude; drag_area_to_mass = Cd A/m [m^2/kg]; rate_limit_per_s the cap
// on 1/2 rho (Cd A/m) |v_rel| (infinity for none).
[[gnu::always_inline]] inline void drag_acceleration(double rho_kg_m3, double drag_area_to_mass_m2_kg,
                                                     double rate_limit_per_s, double x, double y, double vx,
                                                     double vy, double vz, double& ax, double& ay,
                                                     double& az) {
  constexpr double w = constants::kEarthRotationRate_rad_s;
  const double vrx = vx + w * y;
  const double vry = vy - w * x;
  const double vrz = vz;
  const double speed = std::sqrt(vrx * vrx + vry * vry + vrz * vrz);
  double rate = 0.5 * rho_kg_m3 * drag_area_to_mass_m2_kg * speed;
  rate = rate < rate_limit_per_s ? rate : rate_limit_per_s;
  const double f = -rate;
  ax = f * vrx;
  ay = f * vry;
  az = f * vrz;
}

// Drag alone over h_s seconds at a fixed position. With r fixed, k = 1/2 rho (Cd A/m) and omega_E x r
// are constant, so v_rel' = v' = -k |v_rel| v_rel, whose exact solution is
//   v_rel(h) = v_rel(0) / (1 + k |v_rel(0)| h),
// a true flow (drag_flow(-h) undoes drag_flow(h)), valid for negative h while 1 + k |v_rel| h > 0. The
// rate k |v_rel| is capped at rate_limit_per_s as in drag_acceleration; the propagator's cap keeps
// |k |v_rel| h| <= 1/8, so the denominator stays >= 7/8 (finite, bounded) even in Yoshida's negative kick.
// Applied as v -= g v_rel with g = k|v_rel|h / (1 + k|v_rel|h): without drag g = 0 and v is unchanged
// bit for bit.
[[gnu::always_inline]] inline void drag_flow(double rho_kg_m3, double drag_area_to_mass_m2_kg,
                                             double rate_limit_per_s, double x, double y, double h_s,
                                             double& vx, double& vy, double& vz) {
  constexpr double w = constants::kEarthRotationRate_rad_s;
  const double vrx = vx + w * y;
  const double vry = vy - w * x;
  const double vrz = vz;
  const double speed = std::sqrt(vrx * vrx + vry * vry + vrz * vrz);
  double rate = 0.5 * rho_kg_m3 * drag_area_to_mass_m2_kg * speed;
  rate = rate < rate_limit_per_s ? rate : rate_limit_per_s;
  const double rate_h = rate * h_s;
  const double g = rate_h / (1.0 + rate_h);
  vx -= g * vrx;
  vy -= g * vry;
  vz -= g * vrz;
}

}  // namespace kessler
