// What conjunction detection reports: one close approach of two objects, and the settings that decide
// what counts as one (the paper's section "Conjunction Tracking").
#pragma once

#include <cstdint>

#include <Eigen/Core>

#include "core/population/population.hpp"

namespace kessler {

enum class NarrowPhase {
  kLinear,   // the paper: closest approach of straight-line motions inside the step, clamped to [0, dt]
  kHermite,  // default: cubic Hermite motion per object, minimum of the degree-6 squared distance
};

struct ConjunctionSettings {
  NarrowPhase narrow_phase = NarrowPhase::kHermite;
  // Threshold: d <= kappa_max (r1 + r2), unless screening_distance_m > 0, then d <= screening_distance_m.
  double kappa_max = 10.0;
  double screening_distance_m = 0.0;
  // The paper's rules: two active objects evade (an evasion event, not a conjunction); an active and a
  // passive object count only when the passive one is smaller than this radius; two passive always.
  bool active_pairs_evade = true;
  double active_passive_max_passive_radius_m = 0.10;
};

enum class EncounterKind : std::uint8_t {
  kConjunction = 0,  // d <= threshold
  kCollision = 1,    // d <= r1 + r2 (also a conjunction)
  kEvasion = 2,      // two active objects within the threshold: presumed to manoeuvre
};

// One close approach: a local minimum of the pair's distance within the threshold. id1 < id2.
struct Encounter {
  ObjectId id1 = 0;
  ObjectId id2 = 0;
  double tca_s = 0.0;  // time of closest approach, seconds since the scenario epoch
  double miss_distance_m = 0.0;
  double relative_speed_m_s = 0.0;
  double kappa = 0.0;  // miss_distance / (r1 + r2)
  EncounterKind kind = EncounterKind::kConjunction;
  Eigen::Vector3d r1_m, v1_m_s, r2_m, v2_m_s;  // TEME of epoch at the time of closest approach
};

// Canonical order of encounters: time, then ids. Thread count never changes it.
inline bool canonical_less(const Encounter& a, const Encounter& b) {
  if (a.tca_s != b.tca_s) return a.tca_s < b.tca_s;
  if (a.id1 != b.id1) return a.id1 < b.id1;
  return a.id2 < b.id2;
}

}  // namespace kessler
