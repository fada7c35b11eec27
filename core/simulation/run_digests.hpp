// What identifies a run and fingerprints its results (SHA-256, core/simulation/sha256.hpp):
//  - the configuration key: the fields of a SimulationConfig that shape results, so a checkpoint is
//    resumed only under the configuration that wrote it;
//  - the events digest: every numbered event, its tag, sequence number and every field (doubles by
//    their bits), chained in sequence order;
//  - the state digest: each object's id and state at the end.
// Two runs with the same digests produced the same events and the same final population, bit for bit.
#pragma once

#include <cstdint>
#include <string>

#include "core/population/population.hpp"
#include "core/simulation/events.hpp"
#include "core/simulation/sha256.hpp"
#include "core/simulation/simulation.hpp"

namespace kessler {

std::string config_key(const SimulationConfig& config);

// One event into the events digest.
void hash_encounter(Sha256& h, std::uint64_t seq, const Encounter& e);
void hash_burn_up(Sha256& h, std::uint64_t seq, const BurnUp& b);
void hash_breakup(Sha256& h, std::uint64_t seq, const BreakupReport& b);
void hash_lifecycle(Sha256& h, std::uint64_t seq, const LifecycleReport& e);
void hash_progress(Sha256& h, std::uint64_t seq, const Progress& p);

std::string state_digest(const Population& population);

}  // namespace kessler
