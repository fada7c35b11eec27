#include "core/decay/orbit_averaged_drag.hpp"

#include <cmath>
#include <numbers>

#include "core/decay/observed_decay.hpp"
#include "core/physics/constants.hpp"

namespace kessler {

int orbit_average_samples(double eccentricity) {
  return eccentricity < 0.02 ? 24 : 72;
}

std::optional<double> orbit_averaged_decay_per_unit_ballistic(const Sgp4Record& record, const UtcEpoch& epoch,
                                                              const DensityAt& density) {
  if (record.init_error != Sgp4Error::kNone || !(record.no_unkozai > 0.0)) return std::nullopt;
  constexpr double kTwoPi = 2.0 * std::numbers::pi;
  constexpr double mu = constants::kEarthMu_m3_s2;
  constexpr double w = constants::kEarthRotationRate_rad_s;
  const double a = sgp4_mean_semi_major_axis_m(record);
  const double e = record.ecco;
  const int samples = orbit_average_samples(e);
  // The eccentric anomaly at epoch, from the mean anomaly (Newton on Kepler's equation).
  double e0 = record.mo;
  for (int k = 0; k < 20; ++k) e0 -= (e0 - e * std::sin(e0) - record.mo) / (1.0 - e * std::cos(e0));
  const double m0 = e0 - e * std::sin(e0);
  double sum = 0.0, weights = 0.0;
  for (int k = 0; k < samples; ++k) {
    const double ecc_anomaly = e0 + kTwoPi * k / samples;
    const double minutes = (ecc_anomaly - e * std::sin(ecc_anomaly) - m0) / record.no_unkozai;
    const Sgp4State s = sgp4_propagate(record, minutes);
    if (s.error != Sgp4Error::kNone) return std::nullopt;
    const Eigen::Vector3d r(s.position_km[0] * 1e3, s.position_km[1] * 1e3, s.position_km[2] * 1e3);
    const Eigen::Vector3d v(s.velocity_km_s[0] * 1e3, s.velocity_km_s[1] * 1e3, s.velocity_km_s[2] * 1e3);
    const Eigen::Vector3d v_rel(v.x() + w * r.y(), v.y() - w * r.x(), v.z());
    const double rho = density(epoch.plus_seconds(minutes * 60.0), r);
    const double power = -0.5 * rho * v_rel.norm() * v.dot(v_rel);  // v . a_drag per unit Cd A/m
    const double weight = 1.0 - e * std::cos(ecc_anomaly);
    sum += weight * 2.0 * a * a / mu * power;
    weights += weight;
  }
  return sum / weights;
}

}  // namespace kessler
