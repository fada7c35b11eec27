#include "core/traffic/lifecycle.hpp"

#include <cmath>

#include "core/physics/atmosphere.hpp"
#include "core/physics/constants.hpp"
#include "core/random/counter_random.hpp"

namespace kessler {

bool disposal_succeeds(std::uint64_t seed, ObjectId id, double success_probability) {
  return random_uniform(seed, id, RandomPurpose::kDisposal, 0) < success_probability;
}

double circular_decay_years(double altitude_m, double inclination_rad, double drag_m2_kg,
                            double burn_up_altitude_m, const DensityTable& table) {
  if (!(drag_m2_kg > 0.0)) return INFINITY;
  constexpr double kStep_m = 1000.0;
  const double mu = constants::kEarthMu_m3_s2, re = constants::kEarthEquatorialRadius_m;
  double seconds = 0.0;
  // dt = da / (rho Cd (A/m) sqrt(mu a)), midpoint rule per 1 km shell.
  for (double h = burn_up_altitude_m; h < altitude_m; h += kStep_m) {
    const double dh = std::min(kStep_m, altitude_m - h);
    const double mid = h + 0.5 * dh;
    const double rho = table.density_kg_m3(mid);
    const double a = re + mid;
    const double f =
        1.0 - constants::kEarthRotationRate_rad_s * a * std::cos(inclination_rad) / std::sqrt(mu / a);
    seconds += dh / (rho * drag_m2_kg * std::sqrt(mu * a) * f * f);
  }
  return seconds / (365.25 * 86400.0);
}

double disposal_altitude_m(double target_years, double inclination_rad, double drag_m2_kg,
                           double burn_up_altitude_m, double ceiling_m, const DensityTable& table) {
  auto years = [&](double h) {
    return circular_decay_years(h, inclination_rad, drag_m2_kg, burn_up_altitude_m, table);
  };
  double lo = burn_up_altitude_m, hi = ceiling_m;
  if (years(hi) <= target_years) return hi;
  while (hi - lo > 100.0) {
    const double mid = 0.5 * (lo + hi);
    (years(mid) > target_years ? hi : lo) = mid;
  }
  return lo;
}

void move_to_circular_orbit(double radius_m, Eigen::Vector3d& position_m, Eigen::Vector3d& velocity_m_s) {
  const Eigen::Vector3d r_hat = position_m.normalized();
  const Eigen::Vector3d h_hat = position_m.cross(velocity_m_s).normalized();
  position_m = radius_m * r_hat;
  velocity_m_s = std::sqrt(constants::kEarthMu_m3_s2 / radius_m) * h_hat.cross(r_hat);
}

}  // namespace kessler
