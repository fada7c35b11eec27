#include "core/catalog/object_properties.hpp"

#include <algorithm>
#include <cmath>

#include "core/physics/constants.hpp"
#include "core/random/counter_random.hpp"

namespace kessler {

namespace {
constexpr double kPi = 3.14159265358979323846;
}

double radius_from_rcs_m(double rcs_m2) {
  return std::sqrt(rcs_m2 / kPi);
}

double sample_radius_m(const SizeSampling& s, RcsSizeClass size_class, std::uint64_t seed, std::uint64_t id) {
  if (size_class == RcsSizeClass::kUnknown) size_class = s.unknown_as;
  const RadiusDistribution& d = size_class == RcsSizeClass::kSmall   ? s.small
                                : size_class == RcsSizeClass::kLarge ? s.large
                                                                     : s.medium;
  for (std::uint64_t k = 0; k < 64; ++k) {
    const double r = d.mean_m + d.stddev_m * random_normal(seed, id, RandomPurpose::kRadius, k);
    if (r >= s.min_radius_m) return r;
  }
  return s.min_radius_m;
}

double mass_from_radius_kg(double r) {
  const double volume = 4.0 / 3.0 * kPi * r * r * r;
  if (r <= 0.01) return volume * 2698.9;
  return volume * 92.937 * std::pow(2.0 * r, -0.74);
}

double drag_area_to_mass_from_bstar(double bstar) {
  return 2.0 * bstar / constants::kBstarRho0_kg_m2_per_er;
}

double drag_area_to_mass_from_size(double r, double m, double cd) {
  return cd * kPi * r * r / m;
}

double srp_area_to_mass(double r, double m) {
  return kPi * r * r / m;
}

}  // namespace kessler
