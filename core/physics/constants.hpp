// Physical constants of the force model, in SI units, each with its source. The one place they live.
#pragma once

#include <numbers>

namespace kessler::constants {

// Earth's gravitational parameter [m^3/s^2] (EGM2008 / WGS-84 value, as in the paper's propagator).
inline constexpr double kEarthMu_m3_s2 = 3.986004418e14;
// Reference radius of the gravity field model [m] (EGM96/EGM2008).
inline constexpr double kEarthGravityRadius_m = 6378136.3;
// Equatorial radius used for altitudes and burn-up [m] (WGS-84).
inline constexpr double kEarthEquatorialRadius_m = 6378137.0;
// Fully normalised gravity field coefficients (EGM96): C20, C22, S22.
inline constexpr double kC20Normalised = -4.84165371736e-4;
inline constexpr double kC22Normalised = 2.43914352398e-6;
inline constexpr double kS22Normalised = -1.40016683654e-6;
// Earth's rotation rate [rad/s] (IERS, mean sidereal rate).
inline constexpr double kEarthRotationRate_rad_s = 7.292115146706979e-5;

// Astronomical unit [m] (IAU 2012).
inline constexpr double kAstronomicalUnit_m = 1.495978707e11;
// Solar radiation pressure at 1 AU [N/m^2] (the paper's value).
inline constexpr double kSolarPressureAt1Au_N_m2 = 4.56e-6;
// Sun's mean radius [m], for the shadow geometry.
inline constexpr double kSunRadius_m = 6.957e8;

// Reference density of the BSTAR drag term [kg/m^2 per Earth radius]: B* [1/ER] = (Cd A/m) rho0 / 2,
// so Cd A/m [m^2/kg] = 2 B* / rho0 (Hoots & Roehrich, Spacetrack Report #3).
inline constexpr double kBstarRho0_kg_m2_per_er = 0.15696615;
inline constexpr double kBstarEarthRadius_m = 6378135.0;  // WGS-72, the radius BSTAR is defined with
// Default drag coefficient when an object has no BSTAR (paper, after Cook 1965).
inline constexpr double kDefaultDragCoefficient = 2.2;

// Seconds per day.
inline constexpr double kSecondsPerDay = 86400.0;

}  // namespace kessler::constants
