// Counter-based random numbers: each draw is a pure function of (seed, object id, purpose, counter),
// so a population comes out the same whatever the order or thread count that builds it.
#pragma once

#include <cmath>
#include <cstdint>

namespace kessler {

// What a draw is for, so that different uses of one object's numbers never coincide.
enum class RandomPurpose : std::uint64_t {
  kRadius = 1,
  kSyntheticOrbit = 2,
  kSyntheticSize = 3,
  kSyntheticStatus = 4,
  // Breakup fragments (core/breakup/): id is the event id; the counter is the fragment's draw index i
  // (or 2i and 2i + 1 for a pair of draws). core/breakup/README.md lists them.
  kBreakupSize = 16,
  kBreakupParent = 17,
  kBreakupAreaToMassBranch = 18,
  kBreakupNormal = 19,
  kBreakupDirection = 20,
  // Launch traffic and lifecycles (core/traffic/): id is the plan row (launch orbits) or the object
  // (disposal).
  kLaunchOrbit = 32,
  kDisposal = 33,
  // Collision avoidance below full efficiency (core/conjunctions/pair_rules.hpp): id mixes the pair,
  // the counter is the bits of the time of closest approach.
  kEvasion = 34,
  kRemainingLifetime = 35,  // an active catalog payload's remaining operational lifetime (id: the object)
};

// SplitMix64's finaliser (Steele, Lea & Flood 2014): a bijective 64-bit mix.
inline std::uint64_t mix64(std::uint64_t z) {
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}

inline std::uint64_t random_bits(std::uint64_t seed, std::uint64_t id, RandomPurpose purpose,
                                 std::uint64_t counter) {
  std::uint64_t h = mix64(seed + 0x9E3779B97F4A7C15ULL);
  h = mix64(h ^ (id + 0x632BE59BD9B4E019ULL));
  h = mix64(h ^ (static_cast<std::uint64_t>(purpose) * 0x8CB92BA72F3D8DD7ULL));
  return mix64(h ^ (counter + 0xD6E8FEB86659FD93ULL));
}

// Uniform in (0, 1).
inline double random_uniform(std::uint64_t seed, std::uint64_t id, RandomPurpose purpose,
                             std::uint64_t counter) {
  return (static_cast<double>(random_bits(seed, id, purpose, counter) >> 11) + 0.5) * 0x1.0p-53;
}

// Standard normal by Box-Muller from the uniforms of counters 2k and 2k+1.
inline double random_normal(std::uint64_t seed, std::uint64_t id, RandomPurpose purpose, std::uint64_t k) {
  const double u1 = random_uniform(seed, id, purpose, 2 * k);
  const double u2 = random_uniform(seed, id, purpose, 2 * k + 1);
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * 3.14159265358979323846 * u2);
}

}  // namespace kessler
