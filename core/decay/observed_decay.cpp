#include "core/decay/observed_decay.hpp"

#include <cmath>

#include "core/sgp4/wgs72.hpp"

namespace kessler {

double sgp4_mean_semi_major_axis_m(const Sgp4Record& record) {
  // a = (ke / n)^(2/3) Earth radii, n in rad/min (SGP4's canonical units).
  return std::pow(sgp4::kXke / record.no_unkozai, 2.0 / 3.0) * sgp4::kEarthRadius_km * 1.0e3;
}

std::optional<double> observed_decay_rate_m_s(const MeanElements& elements, const Sgp4Record& record,
                                              DecaySignal signal) {
  if (record.init_error != Sgp4Error::kNone || !(record.no_unkozai > 0.0)) return std::nullopt;
  const double a_m = sgp4_mean_semi_major_axis_m(record);
  if (signal == DecaySignal::kMeanMotionDerivative) {
    // The element set publishes n-dot / 2 [rad/min^2].
    const double n_dot_rad_s2 = 2.0 * elements.mean_motion_dot_rad_min2 / 3600.0;
    const double n_rad_s = record.no_unkozai / 60.0;
    if (!(n_dot_rad_s2 > 0.0)) return std::nullopt;
    return -(2.0 / 3.0) * a_m / n_rad_s * n_dot_rad_s2;
  }
  if (!(record.bstar > 0.0) || !(record.cc1 > 0.0)) return std::nullopt;
  return -2.0 * a_m * record.cc1 / 60.0;  // C1 is per minute
}

}  // namespace kessler
