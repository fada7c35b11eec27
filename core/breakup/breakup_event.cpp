#include "core/breakup/breakup_event.hpp"

#include <cmath>

namespace kessler {
namespace {

void require(bool ok, const std::string& field, const std::string& reason) {
  if (!ok) throw BreakupInputError(field, reason);
}

void validate_parent(const BreakupParent& p, const std::string& name) {
  require(std::isfinite(p.mass_kg), name + ".mass_kg", "must be finite");
  require(p.mass_kg > 0.0, name + ".mass_kg", "must be positive");
  require(std::isfinite(p.characteristic_length_m), name + ".characteristic_length_m", "must be finite");
  require(p.characteristic_length_m > 0.0, name + ".characteristic_length_m", "must be positive");
  for (int k = 0; k < 3; ++k) {
    require(std::isfinite(p.position_m[k]), name + ".position_m", "must be finite");
    require(std::isfinite(p.velocity_m_s[k]), name + ".velocity_m_s", "must be finite");
  }
}

}  // namespace

void validate_breakup_event(const BreakupEvent& event) {
  const bool collision = event.kind == BreakupKind::kCollision;
  require(event.parents.size() == (collision ? 2u : 1u), "parents",
          collision ? "a collision needs exactly 2 parents" : "an explosion needs exactly 1 parent");
  for (std::size_t i = 0; i < event.parents.size(); ++i)
    validate_parent(event.parents[i], "parents[" + std::to_string(i) + "]");
  if (event.impact_speed_m_s) {
    require(collision, "impact_speed_m_s", "only a collision has an impact speed");
    require(std::isfinite(*event.impact_speed_m_s), "impact_speed_m_s", "must be finite");
    require(*event.impact_speed_m_s >= 0.0, "impact_speed_m_s", "must not be negative");
  }
  require(std::isfinite(event.explosion_scale), "explosion_scale", "must be finite");
  require(event.explosion_scale >= 0.0, "explosion_scale", "must not be negative");
  const double lc = event.min_characteristic_length_m;
  require(std::isfinite(lc), "min_characteristic_length_m", "must be finite");
  require(lc > 0.0 && lc <= 1.0, "min_characteristic_length_m", "must be in (0, 1] m");
  require(event.max_fragments_per_event > 0, "max_fragments_per_event", "must be positive");
}

}  // namespace kessler
