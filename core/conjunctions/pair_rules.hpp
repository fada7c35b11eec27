// The paper's rules on who takes part in a conjunction: operated satellites evade what they can see.
#pragma once

#include <bit>

#include "core/conjunctions/encounter.hpp"
#include "core/random/counter_random.hpp"

namespace kessler {

// The kind of a close approach within the threshold:
//   - two active objects: an evasion when settings.active_pairs_evade (they manoeuvre);
//   - an active and a passive object: a conjunction only when the passive one is smaller than
//     settings.active_passive_max_passive_radius_m (too small to be tracked); otherwise the operator
//     sees it coming and evades: an evasion;
//   - two passive objects: always a conjunction;
// and a conjunction at d <= r1 + r2 is a collision. Below an evasion efficiency of 1, an active-passive
// approach the operator would evade is evaded only when `evades` (evasion_draw).
// `evades`: whether the operator of an active object evades a trackable passive one this time
// (evasion_draw; true under the paper's rule).
inline EncounterKind classify_encounter(const ConjunctionSettings& settings, ObjectStatus status1,
                                        double radius1_m, ObjectStatus status2, double radius2_m,
                                        double distance_m, bool evades = true) {
  const bool active1 = status1 == ObjectStatus::kActive, active2 = status2 == ObjectStatus::kActive;
  if (active1 && active2) {
    if (settings.active_pairs_evade) return EncounterKind::kEvasion;
  } else if (active1 || active2) {
    const double passive_radius = active1 ? radius2_m : radius1_m;
    if (!(passive_radius < settings.active_passive_max_passive_radius_m) && evades)
      return EncounterKind::kEvasion;
  }
  return distance_m <= radius1_m + radius2_m ? EncounterKind::kCollision : EncounterKind::kConjunction;
}

// Whether an active-passive approach of ids id1 < id2 at tca_s is evaded under
// settings.active_passive_evasion_efficiency: always at 1, else a keyed uniform draw below it.
inline bool evasion_draw(const ConjunctionSettings& settings, ObjectId id1, ObjectId id2, double tca_s) {
  if (settings.active_passive_evasion_efficiency >= 1.0) return true;
  const std::uint64_t pair = mix64(id1) ^ id2;
  return random_uniform(settings.seed, pair, RandomPurpose::kEvasion, std::bit_cast<std::uint64_t>(tca_s)) <
         settings.active_passive_evasion_efficiency;
}

}  // namespace kessler
