// The Sun's geocentric position from the Astronomical Almanac's low-precision formula (about 0.01 deg
// from 1950 to 2050; also Vallado alg. 29). The result is in the mean equator and equinox of date, which
// differs from TEME by the equation of the equinoxes (< 1.2 arcsec): negligible for SRP.
#pragma once

#include <Eigen/Core>

#include "core/time/epoch.hpp"

namespace kessler {

// Sun position [m], Earth-centred, TEME/mean-of-date.
Eigen::Vector3d sun_position_m(const UtcEpoch& when);

}  // namespace kessler
