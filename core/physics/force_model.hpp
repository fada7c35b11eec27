// The full force model of one object at one instant: Kepler + J2 + C22/S22 + drag + SRP, each switched
// by ForceModelSettings. Two faces of the same arithmetic:
//  - ForceModel::acceleration(r, v, t, properties): one object, for tests and tools;
//  - ForceModel::instant(t) + accelerate<Model>(instant, ...): the scalars of one instant (Earth angle,
//    Sun position, switched coefficients) computed once, then a per-object inline kernel of + - * / sqrt
//    and deterministic_exp only, which the propagator's loop vectorises. Both give the same bits.
//  - ForceModel::kick / kick<Model>: the propagator's velocity update over h seconds at a fixed position
//    with drag coupled at every kick (DragCoupling::kEveryKick): half of the drag as its exact flow, the
//    velocity-independent terms as a plain kick, the other half of the drag (Strang splitting: the kick
//    is time-symmetric with drag; drag.hpp, drag_flow).
//  - ForceModel::conservative_kick / drag_flow (conservative_kick, drag_flow_at<Model>): the two halves
//    apart, for drag coupled at the step's ends (DragCoupling::kStepEnds).
// A switched-off term has a zero coefficient, so it adds exactly zero.
#pragma once

#include <limits>

#include <Eigen/Core>

#include "core/physics/atmosphere.hpp"
#include "core/physics/drag.hpp"
#include "core/physics/earth_rotation.hpp"
#include "core/physics/force_model_settings.hpp"
#include "core/physics/gravity.hpp"
#include "core/physics/msis_grid.hpp"
#include "core/physics/solar_radiation_pressure.hpp"
#include "core/time/epoch.hpp"

namespace kessler {

// What the force model needs of an object besides its state.
struct ObjectForceProperties {
  double drag_area_to_mass_m2_kg = 0.0;  // Cd A/m
  double srp_area_to_mass_m2_kg = 0.0;   // A/m
};

// Every per-instant scalar of the force model.
struct ForceInstant {
  double t_s = 0.0;  // seconds since the scenario epoch
  double mu_m3_s2 = 0.0;
  double j2_mu_r2 = 0.0;
  double c22_mu_r2 = 0.0;
  double s22_mu_r2 = 0.0;
  double cos_theta = 1.0;  // Earth rotation angle theta(t)
  double sin_theta = 0.0;
  double drag_scale = 0.0;  // 1 with drag on, 0 off
  // Cap on 1/2 rho (Cd A/m) |v_rel| [1/s] (drag.hpp); the propagator sets it from its step.
  double drag_rate_limit_per_s = std::numeric_limits<double>::infinity();
  double srp_p_au2 = 0.0;  // P AU^2 [N], 0 with SRP off
  SunGeometry sun;
  // Density table arrays (DensityTable::standard()).
  const double* ln_rho = nullptr;
  const double* slope_per_m = nullptr;
  int cells = 0;
  // NRLMSISE-00's grid of this instant's slot (msis_grid.hpp), the Sun's direction in the equatorial
  // plane, and the grid's owner (keeps it alive while the instant is in use).
  const float* msis_grid = nullptr;
  double sun_eq_x = 1.0, sun_eq_y = 0.0;
  std::shared_ptr<const float[]> msis_grid_owner;
};

template <AtmosphereModel kAtmosphere>
[[gnu::always_inline]] inline double atmosphere_density(const ForceInstant& f, double x, double y, double z,
                                                        double altitude_m) {
  if constexpr (kAtmosphere == AtmosphereModel::kDensityTable)
    return DensityTable::density_at(f.ln_rho, f.slope_per_m, f.cells, altitude_m);
  else if constexpr (kAtmosphere == AtmosphereModel::kNrlmsise00)
    return msis_grid_density(f.msis_grid, f.sun_eq_x, f.sun_eq_y, x, y, z, altitude_m);
  else
    return exponential_fit_density_kg_m3(altitude_m);
}

// Acceleration [m/s^2] of one object at the instant f.
template <AtmosphereModel kAtmosphere>
[[gnu::always_inline]] inline void accelerate(const ForceInstant& f, double x, double y, double z, double vx,
                                              double vy, double vz, double drag_area_to_mass,
                                              double srp_area_to_mass, double& ax, double& ay, double& az) {
  const double r2 = x * x + y * y + z * z;
  const double r = std::sqrt(r2);
  const double inv_r = 1.0 / r;
  double kx, ky, kz, jx, jy, jz, cx, cy, cz, dx, dy, dz, sx, sy, sz;
  gravity::kepler_acceleration(f.mu_m3_s2, x, y, z, inv_r, kx, ky, kz);
  gravity::j2_acceleration(f.j2_mu_r2, x, y, z, inv_r, jx, jy, jz);
  gravity::c22_s22_acceleration(f.c22_mu_r2, f.s22_mu_r2, f.cos_theta, f.sin_theta, x, y, z, inv_r, cx, cy,
                                cz);
  const double rho = atmosphere_density<kAtmosphere>(f, x, y, z, r - constants::kEarthEquatorialRadius_m);
  drag_acceleration(rho, f.drag_scale * drag_area_to_mass, f.drag_rate_limit_per_s, x, y, vx, vy, vz, dx, dy,
                    dz);
  srp_acceleration(f.srp_p_au2, f.sun, srp_area_to_mass, x, y, z, sx, sy, sz);
  // Small terms first, then the central term: a fixed order, the same in every path.
  ax = kx + (jx + cx + dx + sx);
  ay = ky + (jy + cy + dy + sy);
  az = kz + (jz + cz + dz + sz);
}

// The velocity-independent kick: v += h_s (Kepler + J2 + C22/S22 + SRP) at the fixed position, the same
// terms in the same order as accelerate() without its drag.
[[gnu::always_inline]] inline void conservative_kick(const ForceInstant& f, double h_s, double x, double y,
                                                     double z, double& vx, double& vy, double& vz,
                                                     double srp_area_to_mass) {
  const double r = std::sqrt(x * x + y * y + z * z);
  const double inv_r = 1.0 / r;
  double kx, ky, kz, jx, jy, jz, cx, cy, cz, sx, sy, sz;
  gravity::kepler_acceleration(f.mu_m3_s2, x, y, z, inv_r, kx, ky, kz);
  gravity::j2_acceleration(f.j2_mu_r2, x, y, z, inv_r, jx, jy, jz);
  gravity::c22_s22_acceleration(f.c22_mu_r2, f.s22_mu_r2, f.cos_theta, f.sin_theta, x, y, z, inv_r, cx, cy,
                                cz);
  srp_acceleration(f.srp_p_au2, f.sun, srp_area_to_mass, x, y, z, sx, sy, sz);
  vx += h_s * (kx + (jx + cx + sx));
  vy += h_s * (ky + (jy + cy + sy));
  vz += h_s * (kz + (jz + cz + sz));
}

// The propagator's kick: the velocity after h_s seconds at the fixed position (x, y, z) and instant f
// (h_s may be negative). drag_flow(h/2), then v += h (Kepler + J2 + C22/S22 + SRP), then drag_flow(h/2):
// a symmetric composition of exact sub-flows, so kick(-h) undoes kick(h) (up to rounding and the drag
// cap), which keeps the Yoshida step 4th order with drag. Same terms and density as accelerate(); the
// two halves of drag read one density.
template <AtmosphereModel kAtmosphere>
[[gnu::always_inline]] inline void kick(const ForceInstant& f, double h_s, double x, double y, double z,
                                        double& vx, double& vy, double& vz, double drag_area_to_mass,
                                        double srp_area_to_mass) {
  const double r = std::sqrt(x * x + y * y + z * z);
  const double rho = atmosphere_density<kAtmosphere>(f, x, y, z, r - constants::kEarthEquatorialRadius_m);
  const double cda = f.drag_scale * drag_area_to_mass;
  const double half_h = 0.5 * h_s;
  drag_flow(rho, cda, f.drag_rate_limit_per_s, x, y, half_h, vx, vy, vz);
  conservative_kick(f, h_s, x, y, z, vx, vy, vz, srp_area_to_mass);
  drag_flow(rho, cda, f.drag_rate_limit_per_s, x, y, half_h, vx, vy, vz);
}

// Drag alone over h_s seconds at the fixed position (x, y, z), its exact flow (drag.hpp) with the density
// there at the instant f. Without drag (drag_scale 0) the velocity is unchanged bit for bit.
template <AtmosphereModel kAtmosphere>
[[gnu::always_inline]] inline void drag_flow_at(const ForceInstant& f, double h_s, double x, double y,
                                                double z, double& vx, double& vy, double& vz,
                                                double drag_area_to_mass) {
  const double r = std::sqrt(x * x + y * y + z * z);
  const double rho = atmosphere_density<kAtmosphere>(f, x, y, z, r - constants::kEarthEquatorialRadius_m);
  drag_flow(rho, f.drag_scale * drag_area_to_mass, f.drag_rate_limit_per_s, x, y, h_s, vx, vy, vz);
}

class ForceModel {
 public:
  ForceModel(const ForceModelSettings& settings, const UtcEpoch& epoch);

  const ForceModelSettings& settings() const { return settings_; }
  // NRLMSISE-00's grid (null unless the atmosphere is kNrlmsise00).
  const std::shared_ptr<MsisDensityGrid>& msis_grid() const { return msis_; }
  const UtcEpoch& epoch() const { return epoch_; }

  // The per-instant scalars at t_s seconds since the epoch (a few trig calls and the Sun ephemeris).
  // Without `density`, NRLMSISE-00's grid is left out (null): for instants that never read the density,
  // such as the conservative kicks between drag at the step's ends, whose slots would otherwise cost a
  // pass over the grid each (the grid is a function of the slot alone, so this changes no bit).
  ForceInstant instant(double t_s, bool density = true) const;

  // Acceleration of one object (TEME [m], [m/s]) at t_s seconds since the epoch [m/s^2].
  Eigen::Vector3d acceleration(const Eigen::Vector3d& r_m, const Eigen::Vector3d& v_m_s, double t_s,
                               const ObjectForceProperties& object) const;
  // Same, with a precomputed instant.
  Eigen::Vector3d acceleration(const ForceInstant& instant, const Eigen::Vector3d& r_m,
                               const Eigen::Vector3d& v_m_s, const ObjectForceProperties& object) const;

  // The propagator's kick (kick<Model> above): velocity [m/s] after h_s seconds at the fixed position r_m,
  // the forces taken at the instant (t_s seconds since the epoch). The same bits as the propagator's.
  Eigen::Vector3d kick(const ForceInstant& instant, const Eigen::Vector3d& r_m, const Eigen::Vector3d& v_m_s,
                       double h_s, const ObjectForceProperties& object) const;
  Eigen::Vector3d kick(const Eigen::Vector3d& r_m, const Eigen::Vector3d& v_m_s, double t_s, double h_s,
                       const ObjectForceProperties& object) const;
  // The two halves of a step with drag coupled at its ends: the velocity-independent kick over h_s, and
  // drag's exact flow over h_s, both at the fixed position r_m and the instant (t_s seconds since the
  // epoch). The same bits as the propagator's.
  Eigen::Vector3d conservative_kick(const Eigen::Vector3d& r_m, const Eigen::Vector3d& v_m_s, double t_s,
                                    double h_s, const ObjectForceProperties& object) const;
  Eigen::Vector3d drag_flow(const Eigen::Vector3d& r_m, const Eigen::Vector3d& v_m_s, double t_s, double h_s,
                            const ObjectForceProperties& object) const;

 private:
  ForceModelSettings settings_;
  UtcEpoch epoch_;
  EarthRotation rotation_;
  std::shared_ptr<MsisDensityGrid> msis_;  // with kNrlmsise00; shared by copies
};

}  // namespace kessler
