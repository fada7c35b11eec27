// Test scenarios for conjunction detection: exact Kepler states at every step boundary, and a loop that
// runs the detector over them.
#pragma once

#include <vector>

#include "core/conjunctions/detector.hpp"
#include "tests/conjunctions/kepler_motion.hpp"

namespace kessler::testing {

// States of every object at t = k dt for k = 0..steps, each propagated exactly from t = 0.
inline std::vector<StateArrays> kepler_snapshots(const std::vector<KeplerState>& initial, double dt_s,
                                                 int steps) {
  std::vector<StateArrays> snaps(static_cast<std::size_t>(steps) + 1);
  for (int k = 0; k <= steps; ++k) {
    StateArrays& s = snaps[static_cast<std::size_t>(k)];
    s.resize(initial.size());
    for (std::size_t i = 0; i < initial.size(); ++i) {
      const KeplerState st = kepler_propagate(initial[i], k * dt_s);
      s.set(i, st.r_m, st.v_m_s);
    }
  }
  return snaps;
}

inline std::vector<Encounter> run_detector(const Population& population,
                                           const std::vector<StateArrays>& snaps, double dt_s,
                                           const ConjunctionSettings& settings,
                                           std::size_t* candidate_pairs = nullptr,
                                           const ChunkLayout* chunks = nullptr) {
  ConjunctionDetector detector(settings);
  std::vector<Encounter> events;
  std::size_t pairs = 0;
  for (std::size_t k = 0; k + 1 < snaps.size(); ++k) {
    StepEnds step{static_cast<double>(k) * dt_s, dt_s, &snaps[k], &snaps[k + 1], chunks};
    detector.scan(population, step, events);
    pairs += detector.last_candidate_pairs();
  }
  if (candidate_pairs) *candidate_pairs = pairs;
  return events;
}

// A population of the given states with one radius and status for all, ids 1, 2, ...
inline Population simple_population(const std::vector<KeplerState>& states, double radius_m,
                                    ObjectStatus status = ObjectStatus::kPassive) {
  std::vector<ObjectId> ids;
  for (std::size_t k = 0; k < states.size(); ++k) ids.push_back(k + 1);
  return population_from_states(states, std::vector<double>(states.size(), radius_m),
                                std::vector<ObjectStatus>(states.size(), status), ids);
}

}  // namespace kessler::testing
