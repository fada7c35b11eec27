#include "core/physics/sun_ephemeris.hpp"

#include <cmath>
#include <numbers>

#include "core/physics/constants.hpp"

namespace kessler {

Eigen::Vector3d sun_position_m(const UtcEpoch& when) {
  constexpr double kDeg = std::numbers::pi / 180.0;
  const double n = (when.jd_whole() - 2451545.0) + when.jd_fraction();  // days from J2000.0
  const double mean_longitude_deg = 280.460 + 0.9856474 * n;
  const double mean_anomaly = (357.528 + 0.9856003 * n) * kDeg;
  const double ecliptic_longitude =
      (mean_longitude_deg + 1.915 * std::sin(mean_anomaly) + 0.020 * std::sin(2.0 * mean_anomaly)) * kDeg;
  const double obliquity = (23.439 - 0.0000004 * n) * kDeg;
  const double distance_m =
      (1.00014 - 0.01671 * std::cos(mean_anomaly) - 0.00014 * std::cos(2.0 * mean_anomaly)) *
      constants::kAstronomicalUnit_m;
  return distance_m * Eigen::Vector3d(std::cos(ecliptic_longitude),
                                      std::cos(obliquity) * std::sin(ecliptic_longitude),
                                      std::sin(obliquity) * std::sin(ecliptic_longitude));
}

}  // namespace kessler
