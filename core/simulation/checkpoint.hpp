// Checkpoint bytes: the complete state of a run at a step boundary, self-contained, versioned and
// checksummed. Layout: "KESSLCKP", format version (u32), payload size (u64), payload, SHA-256 of the
// payload. Numbers little-endian; doubles as their bit patterns, so a resumed run continues bit for bit.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/conjunctions/encounter.hpp"
#include "core/population/population.hpp"
#include "core/simulation/breakups.hpp"
#include "core/simulation/events.hpp"

namespace kessler {

// The run's counters are a base: encoded in for_each_counter's order after the seed.
struct CheckpointState : RunCounters {
  std::string config_key;  // hex digest of the result-shaping configuration (refuses another scenario)
  std::int64_t step = 0;   // steps completed
  std::int64_t total_steps = 0;
  std::uint64_t next_seq = 1;
  std::uint64_t seed = 0;  // random draws are keyed by (seed, object id, purpose): no other RNG state
  double wall_s = 0.0;     // wall time spent before this checkpoint (progress and ETA only)
  std::string events_digest_state;          // Sha256 running state over every event so far
  std::vector<Encounter> closest_per_pair;  // the closest encounter of every pair so far (canonical order)
  Population population;
  // The breakups' ids and separating groups (breakups.hpp). Version 1 has none (a run from it has made
  // no fragments); version 2 only the fragment id counter.
  BreakupIds breakups;
  // The launches made and the actives' lifecycles (traffic.hpp); version 4.
  TrafficState traffic;
};

// Version 2 appends next_fragment_id after the population; version 3 the population's types and
// separation groups, the breakup counter and the separating breakups; version 4 the traffic state.
// Versions 1 to 3 are still read.
inline constexpr std::uint32_t kCheckpointVersion = 4;
inline constexpr std::uint32_t kOldestCheckpointVersion = 1;

std::string encode_checkpoint(const CheckpointState& state);
// Throws std::runtime_error ("checkpoint: <reason>") on bytes that are not a sound checkpoint.
CheckpointState decode_checkpoint(const std::string& bytes);

}  // namespace kessler
