// The input of the NASA Standard Breakup Model: what broke up, how, and the keys of its random draws.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace kessler {

enum class BreakupKind { kCollision, kExplosion };

// The model's area-to-mass distributions differ for spacecraft and rocket bodies (upper stages).
enum class BreakupObjectClass { kSpacecraft, kRocketBody };

struct BreakupParent {
  std::uint64_t id = 0;
  double mass_kg = 0.0;
  double characteristic_length_m = 0.0;  // the largest fragment size this parent can give
  BreakupObjectClass object_class = BreakupObjectClass::kSpacecraft;
  std::array<double, 3> position_m{};    // TEME
  std::array<double, 3> velocity_m_s{};  // TEME
};

struct BreakupEvent {
  BreakupKind kind = BreakupKind::kCollision;
  // Collision: two parents; the lighter is the projectile (on equal masses parents[1]). Explosion: one.
  std::vector<BreakupParent> parents;
  // Collision only: the impact speed. Unset: |v0 - v1| of the two parents. Set: this speed, e.g. for an
  // external projectile (an ASAT interceptor) given as parents[1] whose velocity is only approximate.
  std::optional<double> impact_speed_m_s;
  double explosion_scale = 1.0;               // S in N = 6 S Lc^-1.6
  double min_characteristic_length_m = 0.10;  // Lc_min, in (0, 1] m
  bool conserve_mass = true;                  // see core/breakup/README.md
  std::uint64_t max_fragments_per_event = 1'000'000;
  std::uint64_t event_id = 0;  // with the seed, the key of every random draw of this event
  std::uint64_t seed = 0;      // the scenario seed
};

// An event the model cannot take: names the field (e.g. "parents[1].mass_kg") and the reason.
class BreakupInputError : public std::invalid_argument {
 public:
  BreakupInputError(const std::string& field, const std::string& reason)
      : std::invalid_argument("breakup event: " + field + ": " + reason), field_(field) {}
  const std::string& field() const { return field_; }

 private:
  std::string field_;
};

// Throws BreakupInputError for: a kind with the wrong number of parents; a negative, zero or non-finite
// mass or characteristic length; a non-finite position or velocity; an impact speed or explosion scale
// that is negative or non-finite; Lc_min outside (0, 1] m; max_fragments_per_event of 0.
void validate_breakup_event(const BreakupEvent& event);

}  // namespace kessler
