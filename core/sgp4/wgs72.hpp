// The WGS-72 Earth constants SGP4 is defined with (Hoots & Roehrich 1980; Vallado et al. 2006), in the
// model's own units: Earth radii (ER) and minutes.
#pragma once

#include <cmath>

namespace kessler::sgp4 {

inline constexpr double kMu_km3_s2 = 398600.8;
inline constexpr double kEarthRadius_km = 6378.135;
inline const double kXke = 60.0 / std::sqrt(kEarthRadius_km * kEarthRadius_km * kEarthRadius_km /
                                            kMu_km3_s2);  // sqrt(mu) [ER^1.5/min]
inline constexpr double kJ2 = 0.001082616;
inline constexpr double kJ3 = -0.00000253881;
inline constexpr double kJ4 = -0.00000165597;
inline constexpr double kJ3OverJ2 = kJ3 / kJ2;
inline constexpr double kTwoPi = 2.0 * 3.14159265358979323846;
inline constexpr double kPi = 3.14159265358979323846;

}  // namespace kessler::sgp4
