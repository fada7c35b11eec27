#include "core/breakup/energy_and_count.hpp"

#include <algorithm>
#include <cmath>
#include <string>

namespace kessler {

double specific_energy_j_per_g(double target_mass_kg, double projectile_mass_kg, double impact_speed_m_s) {
  // J/kg / 1000 = J/g.
  return projectile_mass_kg * impact_speed_m_s * impact_speed_m_s / (2.0 * target_mass_kg) / 1000.0;
}

double collision_mass_kg(bool catastrophic, double target_mass_kg, double projectile_mass_kg,
                         double impact_speed_m_s) {
  if (catastrophic) return target_mass_kg + projectile_mass_kg;
  const double v_km_s = impact_speed_m_s / 1000.0;
  return projectile_mass_kg * v_km_s * v_km_s;
}

double collision_cumulative_count(double mass_kg, double lc_m) {
  return 0.1 * std::pow(mass_kg, 0.75) * std::pow(lc_m, -kCollisionSizeExponent);
}

double explosion_cumulative_count(double scale, double lc_m) {
  return 6.0 * scale * std::pow(lc_m, -kExplosionSizeExponent);
}

BreakupPlan plan_breakup(const BreakupEvent& event) {
  validate_breakup_event(event);
  BreakupPlan plan;
  plan.lc_min_m = event.min_characteristic_length_m;
  if (event.kind == BreakupKind::kExplosion) {
    plan.catastrophic = true;
    plan.size_exponent = kExplosionSizeExponent;
    plan.lc_max_m = event.parents[0].characteristic_length_m;
    plan.expected_count = explosion_cumulative_count(event.explosion_scale, plan.lc_min_m);
  } else {
    const BreakupParent& a = event.parents[0];
    const BreakupParent& b = event.parents[1];
    plan.target = a.mass_kg > b.mass_kg ? 0 : 1;
    plan.projectile = 1 - plan.target;
    if (event.impact_speed_m_s) {
      plan.impact_speed_m_s = *event.impact_speed_m_s;
    } else {
      const double dx = a.velocity_m_s[0] - b.velocity_m_s[0], dy = a.velocity_m_s[1] - b.velocity_m_s[1],
                   dz = a.velocity_m_s[2] - b.velocity_m_s[2];
      plan.impact_speed_m_s = std::sqrt(dx * dx + dy * dy + dz * dz);
    }
    const double mt = event.parents[plan.target].mass_kg, mp = event.parents[plan.projectile].mass_kg;
    plan.specific_energy_j_per_g = specific_energy_j_per_g(mt, mp, plan.impact_speed_m_s);
    plan.catastrophic = plan.specific_energy_j_per_g >= kCatastrophicThresholdJPerG;
    plan.size_law_mass_kg = collision_mass_kg(plan.catastrophic, mt, mp, plan.impact_speed_m_s);
    plan.size_exponent = kCollisionSizeExponent;
    plan.lc_max_m = std::max(a.characteristic_length_m, b.characteristic_length_m);
    plan.expected_count = collision_cumulative_count(plan.size_law_mass_kg, plan.lc_min_m);
  }
  const double limit = static_cast<double>(event.max_fragments_per_event);
  if (!(std::floor(plan.expected_count) <= limit))  // also catches NaN and infinity
    throw BreakupInputError("max_fragments_per_event", "the event gives " +
                                                           std::to_string(plan.expected_count) +
                                                           " fragments at Lc_min, more than the limit " +
                                                           std::to_string(event.max_fragments_per_event));
  plan.count =
      plan.lc_max_m > plan.lc_min_m ? static_cast<std::uint64_t>(std::floor(plan.expected_count)) : 0;
  return plan;
}

}  // namespace kessler
