// The paper's catalog view of a run: the closest encounter of each pair of objects over the whole run.
#pragma once

#include <cstddef>
#include <unordered_map>
#include <vector>

#include "core/conjunctions/encounter.hpp"

namespace kessler {

class ClosestEncounterTable {
 public:
  // Keeps e if it is the pair's first encounter or closer than the one kept. Ties are broken by the
  // earlier time of closest approach, so the table never depends on the order of updates (a checkpoint
  // restored through update() gives the same table).
  void update(const Encounter& e);
  std::size_t size() const { return closest_.size(); }
  // One encounter per pair, in canonical order (time, then ids).
  std::vector<Encounter> entries() const;
  void clear() { closest_.clear(); }

 private:
  struct PairKey {
    ObjectId id1, id2;
    bool operator==(const PairKey& o) const { return id1 == o.id1 && id2 == o.id2; }
  };
  struct PairHash {
    std::size_t operator()(const PairKey& k) const {
      std::uint64_t h = k.id1 * 0x9E3779B97F4A7C15ull;
      h ^= (k.id2 + 0x632BE59BD9B4E019ull) + (h << 6) + (h >> 2);
      return static_cast<std::size_t>(h * 0xBF58476D1CE4E5B9ull);
    }
  };
  std::unordered_map<PairKey, Encounter, PairHash> closest_;
};

}  // namespace kessler
