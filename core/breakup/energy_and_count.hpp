// How violent a breakup is and how many fragments it gives: the specific energy that decides a
// catastrophic collision, the mass M of the size law, and the cumulative counts N(>= Lc).
#pragma once

#include <cstddef>
#include <cstdint>

#include "core/breakup/breakup_event.hpp"

namespace kessler {

constexpr double kCatastrophicThresholdJPerG = 40.0;
constexpr double kCollisionSizeExponent = 1.71;  // N(>= Lc) = 0.1 M^0.75 Lc^-1.71
constexpr double kExplosionSizeExponent = 1.6;   // N(>= Lc) = 6 S Lc^-1.6

// E_p = m_p v^2 / (2 m_t) in J/g (v in m/s, masses in kg).
double specific_energy_j_per_g(double target_mass_kg, double projectile_mass_kg, double impact_speed_m_s);

// Catastrophic: M = m_t + m_p. Otherwise M = m_p v^2 with v in km/s.
double collision_mass_kg(bool catastrophic, double target_mass_kg, double projectile_mass_kg,
                         double impact_speed_m_s);

double collision_cumulative_count(double mass_kg, double lc_m);  // 0.1 M^0.75 Lc^-1.71
double explosion_cumulative_count(double scale, double lc_m);    // 6 S Lc^-1.6

// What generation needs, decided before anything is allocated.
struct BreakupPlan {
  bool catastrophic = false;               // explosions: true (the parent fragments entirely)
  double specific_energy_j_per_g = 0.0;    // collisions only
  double impact_speed_m_s = 0.0;           // collisions only
  double size_law_mass_kg = 0.0;           // M (collisions only)
  std::size_t target = 0, projectile = 1;  // indices into parents (collisions only)
  double expected_count = 0.0;             // N(>= Lc_min) as a real number
  std::uint64_t count = 0;                 // floor(expected_count); 0 when Lc_max <= Lc_min
  double size_exponent = 0.0;              // 1.71 or 1.6
  double lc_min_m = 0.0, lc_max_m = 0.0;   // sizes are drawn in [lc_min_m, lc_max_m]
};

// Validates the event (validate_breakup_event) and plans it. Throws BreakupInputError naming
// "max_fragments_per_event" when floor(N(>= Lc_min)) exceeds that limit (or is not finite).
BreakupPlan plan_breakup(const BreakupEvent& event);

}  // namespace kessler
