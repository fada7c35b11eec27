// The paper's physical properties of a catalogued object (after Johnson et al. 2001, NASA breakup
// model): radius from the radar cross section, mass from the radius, and the area-to-mass ratios of
// drag and solar radiation pressure.
#pragma once

#include <cstdint>

#include "core/catalog/satcat.hpp"

namespace kessler {

struct RadiusDistribution {
  double mean_m = 0.0;
  double stddev_m = 0.0;
};

// Radius sampling per RCS size class when no numeric RCS is known. The paper fitted normal
// distributions to CelesTrak's numeric RCS per class without publishing the numbers; these defaults
// are sqrt(RCS/pi) of values typical for each class and stay inside the class bounds (small < 0.178 m,
// medium 0.178..0.564 m, large > 0.564 m) to within one spread.
struct SizeSampling {
  RadiusDistribution small{0.09, 0.04};
  RadiusDistribution medium{0.37, 0.10};
  RadiusDistribution large{1.30, 0.60};
  // Objects with neither a numeric RCS nor a size class are sampled as this class.
  RcsSizeClass unknown_as = RcsSizeClass::kMedium;
  double min_radius_m = 0.005;  // nothing smaller (paper)
};

// r = sqrt(RCS / pi) [m] for RCS in m^2.
double radius_from_rcs_m(double rcs_m2);

// A radius drawn from the class's normal distribution, keyed by (seed, id): redrawn (up to 64 times)
// while below min_radius_m, then clamped to it.
double sample_radius_m(const SizeSampling& sampling, RcsSizeClass size_class, std::uint64_t seed,
                       std::uint64_t id);

// Mass [kg]: (4/3) pi r^3 2698.9 for r <= 1 cm (aluminium spheres), else (4/3) pi r^3 92.937 (2r)^-0.74.
double mass_from_radius_kg(double radius_m);

// Cd A/m [m^2/kg] from B* [1/ER]: 2 B* / rho0 (rho0 = 0.15696615 kg/m^2/ER).
double drag_area_to_mass_from_bstar(double bstar_per_earth_radius);
// Cd A/m [m^2/kg] of a sphere: Cd pi r^2 / m.
double drag_area_to_mass_from_size(double radius_m, double mass_kg, double drag_coefficient);
// A/m [m^2/kg] of a sphere: pi r^2 / m.
double srp_area_to_mass(double radius_m, double mass_kg);

}  // namespace kessler
