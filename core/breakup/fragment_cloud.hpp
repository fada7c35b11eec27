// generate_fragments: the NASA Standard Breakup Model applied to one event, as a structure of arrays.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include "core/breakup/breakup_event.hpp"

namespace kessler {

struct Vec3Arrays {
  std::vector<double> x, y, z;
  void resize(std::size_t n) {
    x.resize(n);
    y.resize(n);
    z.resize(n);
  }
};

// The object a non-catastrophic collision leaves: the target, with the mass the fragments did not take
// and the velocity that conserves the event's momentum.
struct BreakupRemnant {
  std::uint64_t parent_id = 0;
  std::uint8_t parent_index = 0;
  double mass_kg = 0.0;
  double characteristic_length_m = 0.0;
  double radius_m = 0.0;
  std::array<double, 3> position_m{}, velocity_m_s{};
};

struct FragmentCloud {
  // One entry per fragment, in draw order.
  std::vector<std::uint64_t> draw_index;   // the fragment's index among the drawn ones (its random key)
  std::vector<std::uint8_t> parent_index;  // into BreakupEvent::parents
  std::vector<double> characteristic_length_m, area_to_mass_m2_kg, area_m2, mass_kg, radius_m;
  Vec3Arrays delta_v_m_s, velocity_m_s, position_m;  // velocity = parent velocity + delta_v (TEME)

  std::optional<BreakupRemnant> remnant;
  bool catastrophic = false;
  double specific_energy_j_per_g = 0.0;  // collisions (explosions: 0)
  double impact_speed_m_s = 0.0;         // collisions
  double expected_count = 0.0;           // N(>= Lc_min) of the model
  std::uint64_t drawn_count = 0;         // floor(expected_count), before mass conservation
  double parent_mass_kg = 0.0;           // sum of the parents' masses
  double fragment_mass_kg = 0.0;         // sum of mass_kg
  // Mass not in fragments or the remnant: the debris below Lc_min (catastrophic collisions, explosions).
  double unresolved_mass_kg = 0.0;

  std::size_t size() const { return mass_kg.size(); }
};

// Validates the event (BreakupInputError naming the field), counts, then draws every fragment from the
// counter-based generator keyed by (seed, event id, draw index, purpose); OpenMP over fragments, the
// same bits on any thread count. See core/breakup/README.md for the model and the conservation rules.
FragmentCloud generate_fragments(const BreakupEvent& event);

// The same into `cloud`, reusing its arrays' capacity (a caller breaking up many objects allocates once).
// On a BreakupInputError `cloud` is unchanged.
void generate_fragments(const BreakupEvent& event, FragmentCloud& cloud);

}  // namespace kessler
