// The paper's rules on who takes part in a conjunction: operated satellites evade what they can see.
#pragma once

#include "core/conjunctions/encounter.hpp"

namespace kessler {

// The kind of a close approach within the threshold:
//   - two active objects: an evasion when settings.active_pairs_evade (they manoeuvre);
//   - an active and a passive object: a conjunction only when the passive one is smaller than
//     settings.active_passive_max_passive_radius_m (too small to be tracked); otherwise the operator
//     sees it coming and evades: an evasion;
//   - two passive objects: always a conjunction;
// and a conjunction at d <= r1 + r2 is a collision.
inline EncounterKind classify_encounter(const ConjunctionSettings& settings, ObjectStatus status1,
                                        double radius1_m, ObjectStatus status2, double radius2_m,
                                        double distance_m) {
  const bool active1 = status1 == ObjectStatus::kActive, active2 = status2 == ObjectStatus::kActive;
  if (active1 && active2) {
    if (settings.active_pairs_evade) return EncounterKind::kEvasion;
  } else if (active1 || active2) {
    const double passive_radius = active1 ? radius2_m : radius1_m;
    if (!(passive_radius < settings.active_passive_max_passive_radius_m)) return EncounterKind::kEvasion;
  }
  return distance_m <= radius1_m + radius2_m ? EncounterKind::kCollision : EncounterKind::kConjunction;
}

}  // namespace kessler
