// The Earth's rotation angle about the TEME z axis: theta(t) = GMST(epoch) + omega_E t, with GMST from
// the IAU-82 model (UtcEpoch::gmst_rad) and t in seconds since the scenario epoch. Over a run of years
// the linear form departs from a fresh GMST evaluation by far less than the C22/S22 terms resolve.
#pragma once

#include "core/physics/constants.hpp"
#include "core/time/epoch.hpp"

namespace kessler {

class EarthRotation {
 public:
  explicit EarthRotation(const UtcEpoch& epoch) : theta0_rad_(epoch.gmst_rad()) {}
  // Angle from the TEME x axis to the Greenwich meridian [rad] (not reduced to 0..2pi).
  double angle_rad(double t_s) const { return theta0_rad_ + constants::kEarthRotationRate_rad_s * t_s; }

 private:
  double theta0_rad_;
};

}  // namespace kessler
