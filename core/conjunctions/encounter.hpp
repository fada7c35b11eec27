// What conjunction detection reports: one close approach of two objects, and the settings that decide
// what counts as one (the paper's section "Conjunction Tracking").
#pragma once

#include <concepts>
#include <cstdint>
#include <type_traits>

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
  // The share of close approaches of an active object to a trackable passive one that the operator
  // evades (1: all, the paper's rule). Below 1, each approach is evaded when a draw keyed by (seed, the
  // pair, kEvasion, its time of closest approach) falls below it; the others count as conjunctions
  // (and collisions). MOCAT-MC's alpha parameters are the reference for such efficiencies.
  double active_passive_evasion_efficiency = 1.0;
  std::uint64_t seed = 0;  // the run's seed, for those draws
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

// Every field of an Encounter, once, in the order the events digest, the checkpoint and the service's
// proto message visit them: f(name, member) per field, the name being the proto field's. A field added
// here reaches all three (each visitor must then say how it writes the new field's type).
template <class E, class F>  // E: Encounter or const Encounter
requires std::same_as<std::remove_const_t<E>, Encounter>
void for_each_field(E& e, F&& f) {
  f("id1", e.id1);
  f("id2", e.id2);
  f("tca_s", e.tca_s);
  f("miss_distance_m", e.miss_distance_m);
  f("relative_speed_m_s", e.relative_speed_m_s);
  f("kappa", e.kappa);
  f("kind", e.kind);
  f("r1_m", e.r1_m);
  f("v1_m_s", e.v1_m_s);
  f("r2_m", e.r2_m);
  f("v2_m_s", e.v2_m_s);
}

// A member added to Encounter without a line in for_each_field would go missing from the digest, the
// checkpoint and the service: this fails first.
static_assert(sizeof(Encounter) == 2 * 8 + 4 * 8 + 8 + 4 * sizeof(Eigen::Vector3d),
              "Encounter changed: list the new field in for_each_field");

// Canonical order of encounters: time, then ids. Thread count never changes it.
inline bool canonical_less(const Encounter& a, const Encounter& b) {
  if (a.tca_s != b.tca_s) return a.tca_s < b.tca_s;
  if (a.id1 != b.id1) return a.id1 < b.id1;
  return a.id2 < b.id2;
}

}  // namespace kessler
