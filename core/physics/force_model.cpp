#include "core/physics/force_model.hpp"

#include <cmath>

#include "core/physics/sun_ephemeris.hpp"

namespace kessler {

ForceModel::ForceModel(const ForceModelSettings& settings, const UtcEpoch& epoch)
    : settings_(settings), epoch_(epoch), rotation_(epoch) {
  if (settings_.atmosphere == AtmosphereModel::kNrlmsise00) {
    if (!settings_.space_weather && settings_.solar_activity.mode != SolarActivityMode::kConstant)
      settings_.space_weather = SpaceWeather::bundled();
    msis_ = std::make_shared<MsisDensityGrid>(epoch_, settings_.solar_activity, settings_.space_weather);
  }
}

ForceInstant ForceModel::instant(double t_s, bool density) const {
  constexpr double kMu = constants::kEarthMu_m3_s2;
  constexpr double kR2 = constants::kEarthGravityRadius_m * constants::kEarthGravityRadius_m;
  ForceInstant f;
  f.t_s = t_s;
  f.mu_m3_s2 = settings_.kepler ? kMu : 0.0;
  f.j2_mu_r2 = settings_.j2 ? gravity::kJ2 * kMu * kR2 : 0.0;
  f.c22_mu_r2 = settings_.c22_s22 ? gravity::kC22 * kMu * kR2 : 0.0;
  f.s22_mu_r2 = settings_.c22_s22 ? gravity::kS22 * kMu * kR2 : 0.0;
  const double theta = rotation_.angle_rad(t_s);
  f.cos_theta = std::cos(theta);
  f.sin_theta = std::sin(theta);
  f.drag_scale = settings_.drag ? 1.0 : 0.0;
  f.srp_p_au2 = settings_.srp ? constants::kSolarPressureAt1Au_N_m2 * constants::kAstronomicalUnit_m *
                                    constants::kAstronomicalUnit_m
                              : 0.0;
  const Eigen::Vector3d sun = sun_position_m(epoch_.plus_seconds(t_s));
  const Eigen::Vector3d unit = sun.normalized();
  f.sun = {sun.x(),
           sun.y(),
           sun.z(),
           unit.x(),
           unit.y(),
           unit.z(),
           settings_.srp_earth_shadow
               ? constants::kEarthEquatorialRadius_m * constants::kEarthEquatorialRadius_m
               : -1.0};
  const DensityTable& table = DensityTable::standard();
  f.ln_rho = table.ln_rho();
  f.slope_per_m = table.slope_per_m();
  f.cells = table.cells();
  if (msis_ && density) {
    f.msis_grid_owner = msis_->grid_at(t_s);
    f.msis_grid = f.msis_grid_owner.get();
    const double norm = std::sqrt(unit.x() * unit.x() + unit.y() * unit.y());
    f.sun_eq_x = unit.x() / norm;
    f.sun_eq_y = unit.y() / norm;
  }
  return f;
}

Eigen::Vector3d ForceModel::acceleration(const Eigen::Vector3d& r, const Eigen::Vector3d& v, double t_s,
                                         const ObjectForceProperties& object) const {
  return acceleration(instant(t_s), r, v, object);
}

Eigen::Vector3d ForceModel::acceleration(const ForceInstant& f, const Eigen::Vector3d& r,
                                         const Eigen::Vector3d& v,
                                         const ObjectForceProperties& object) const {
  Eigen::Vector3d a;
  if (settings_.atmosphere == AtmosphereModel::kDensityTable)
    accelerate<AtmosphereModel::kDensityTable>(f, r.x(), r.y(), r.z(), v.x(), v.y(), v.z(),
                                               object.drag_area_to_mass_m2_kg, object.srp_area_to_mass_m2_kg,
                                               a.x(), a.y(), a.z());
  else if (settings_.atmosphere == AtmosphereModel::kNrlmsise00)
    accelerate<AtmosphereModel::kNrlmsise00>(f, r.x(), r.y(), r.z(), v.x(), v.y(), v.z(),
                                             object.drag_area_to_mass_m2_kg, object.srp_area_to_mass_m2_kg,
                                             a.x(), a.y(), a.z());
  else
    accelerate<AtmosphereModel::kExponentialFit>(f, r.x(), r.y(), r.z(), v.x(), v.y(), v.z(),
                                                 object.drag_area_to_mass_m2_kg,
                                                 object.srp_area_to_mass_m2_kg, a.x(), a.y(), a.z());
  return a;
}

Eigen::Vector3d ForceModel::kick(const ForceInstant& f, const Eigen::Vector3d& r, const Eigen::Vector3d& v,
                                 double h_s, const ObjectForceProperties& object) const {
  Eigen::Vector3d out = v;
  if (settings_.atmosphere == AtmosphereModel::kDensityTable)
    kessler::kick<AtmosphereModel::kDensityTable>(f, h_s, r.x(), r.y(), r.z(), out.x(), out.y(), out.z(),
                                                  object.drag_area_to_mass_m2_kg,
                                                  object.srp_area_to_mass_m2_kg);
  else if (settings_.atmosphere == AtmosphereModel::kNrlmsise00)
    kessler::kick<AtmosphereModel::kNrlmsise00>(f, h_s, r.x(), r.y(), r.z(), out.x(), out.y(), out.z(),
                                                object.drag_area_to_mass_m2_kg,
                                                object.srp_area_to_mass_m2_kg);
  else
    kessler::kick<AtmosphereModel::kExponentialFit>(f, h_s, r.x(), r.y(), r.z(), out.x(), out.y(), out.z(),
                                                    object.drag_area_to_mass_m2_kg,
                                                    object.srp_area_to_mass_m2_kg);
  return out;
}

Eigen::Vector3d ForceModel::kick(const Eigen::Vector3d& r, const Eigen::Vector3d& v, double t_s, double h_s,
                                 const ObjectForceProperties& object) const {
  return kick(instant(t_s), r, v, h_s, object);
}

Eigen::Vector3d ForceModel::conservative_kick(const Eigen::Vector3d& r, const Eigen::Vector3d& v, double t_s,
                                              double h_s, const ObjectForceProperties& object) const {
  Eigen::Vector3d out = v;
  kessler::conservative_kick(instant(t_s), h_s, r.x(), r.y(), r.z(), out.x(), out.y(), out.z(),
                             object.srp_area_to_mass_m2_kg);
  return out;
}

Eigen::Vector3d ForceModel::drag_flow(const Eigen::Vector3d& r, const Eigen::Vector3d& v, double t_s,
                                      double h_s, const ObjectForceProperties& object) const {
  const ForceInstant f = instant(t_s);
  Eigen::Vector3d out = v;
  const double cda = object.drag_area_to_mass_m2_kg;
  if (settings_.atmosphere == AtmosphereModel::kDensityTable)
    drag_flow_at<AtmosphereModel::kDensityTable>(f, h_s, r.x(), r.y(), r.z(), out.x(), out.y(), out.z(), cda);
  else if (settings_.atmosphere == AtmosphereModel::kNrlmsise00)
    drag_flow_at<AtmosphereModel::kNrlmsise00>(f, h_s, r.x(), r.y(), r.z(), out.x(), out.y(), out.z(), cda);
  else
    drag_flow_at<AtmosphereModel::kExponentialFit>(f, h_s, r.x(), r.y(), r.z(), out.x(), out.y(), out.z(),
                                                   cda);
  return out;
}

}  // namespace kessler
