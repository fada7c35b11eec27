#include "core/traffic/orbit_elements.hpp"

#include <cmath>
#include <numbers>

#include "core/physics/constants.hpp"

namespace kessler {

OrbitElements elements_from_altitudes(double perigee_altitude_m, double apogee_altitude_m,
                                      double inclination_rad) {
  const double rp = constants::kEarthEquatorialRadius_m + perigee_altitude_m;
  const double ra = constants::kEarthEquatorialRadius_m + apogee_altitude_m;
  OrbitElements el;
  el.semi_major_axis_m = 0.5 * (rp + ra);
  el.eccentricity = (ra - rp) / (ra + rp);
  el.inclination_rad = inclination_rad;
  return el;
}

double eccentric_anomaly(double mean_anomaly_rad, double e) {
  const double m = std::remainder(mean_anomaly_rad, 2.0 * std::numbers::pi);
  double ea = e < 0.8 ? m : std::numbers::pi;
  for (int k = 0; k < 50; ++k) {
    const double f = ea - e * std::sin(ea) - m;
    const double step = f / (1.0 - e * std::cos(ea));
    ea -= step;
    if (std::fabs(step) < 1e-15) break;
  }
  return ea;
}

void state_from_elements(const OrbitElements& el, Eigen::Vector3d& position_m,
                         Eigen::Vector3d& velocity_m_s) {
  const double a = el.semi_major_axis_m, e = el.eccentricity;
  const double ea = eccentric_anomaly(el.mean_anomaly_rad, e);
  const double b = a * std::sqrt(1.0 - e * e);
  const double r = a * (1.0 - e * std::cos(ea));
  const double n = std::sqrt(constants::kEarthMu_m3_s2 / (a * a * a));
  // In the perifocal frame (x to perigee), then rotated by argp, inclination and RAAN.
  const Eigen::Vector3d p(a * (std::cos(ea) - e), b * std::sin(ea), 0.0);
  const Eigen::Vector3d v(-a * n * a / r * std::sin(ea), b * n * a / r * std::cos(ea), 0.0);
  const double cO = std::cos(el.raan_rad), sO = std::sin(el.raan_rad);
  const double ci = std::cos(el.inclination_rad), si = std::sin(el.inclination_rad);
  const double cw = std::cos(el.argument_of_perigee_rad), sw = std::sin(el.argument_of_perigee_rad);
  Eigen::Matrix3d rot;
  rot << cO * cw - sO * sw * ci, -cO * sw - sO * cw * ci, sO * si,  //
      sO * cw + cO * sw * ci, -sO * sw + cO * cw * ci, -cO * si,    //
      sw * si, cw * si, ci;
  position_m = rot * p;
  velocity_m_s = rot * v;
}

OrbitElements advance(const OrbitElements& el, double dt_s) {
  OrbitElements out = el;
  const double a = el.semi_major_axis_m;
  out.mean_anomaly_rad =
      std::remainder(el.mean_anomaly_rad + std::sqrt(constants::kEarthMu_m3_s2 / (a * a * a)) * dt_s,
                     2.0 * std::numbers::pi);
  return out;
}

}  // namespace kessler
