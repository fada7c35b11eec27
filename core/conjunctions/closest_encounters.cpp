#include "core/conjunctions/closest_encounters.hpp"

#include <algorithm>

namespace kessler {
namespace {

// Strict "closer" order on two encounters of the same pair: distance, then time.
bool closer(const Encounter& a, const Encounter& b) {
  if (a.miss_distance_m != b.miss_distance_m) return a.miss_distance_m < b.miss_distance_m;
  return a.tca_s < b.tca_s;
}

}  // namespace

void ClosestEncounterTable::update(const Encounter& e) {
  const PairKey key{std::min(e.id1, e.id2), std::max(e.id1, e.id2)};
  auto [it, inserted] = closest_.try_emplace(key, e);
  if (!inserted && closer(e, it->second)) it->second = e;
}

std::vector<Encounter> ClosestEncounterTable::entries() const {
  std::vector<Encounter> out;
  out.reserve(closest_.size());
  for (const auto& [key, e] : closest_) out.push_back(e);
  std::sort(out.begin(), out.end(), canonical_less);
  return out;
}

}  // namespace kessler
