// Rendering of run events and summaries for the CLI, shared by `run --local` and the remote watch
// commands so both end with the same summary keys: one JSON object per line, or aligned table rows.
#pragma once

#include <cstdint>
#include <string>

#include "core/scenario/run_builder.hpp"
#include "core/simulation/events.hpp"
#include "core/time/epoch.hpp"

namespace kessler::cli {

// The objects' names of an encounter, empty where the population has none.
struct EncounterNames {
  std::string name1, name2;
};

// JSON lines. Doubles are written with 17 significant digits, so values round-trip bit for bit.
// Encounters carry both objects' names and their states at TCA (TEME, m and m/s).
std::string encounter_json(std::uint64_t seq, const Encounter& e, const UtcEpoch& epoch,
                           const EncounterNames& names = {});
std::string burn_up_json(std::uint64_t seq, const BurnUp& b, const UtcEpoch& epoch);
std::string progress_json(std::uint64_t seq, const Progress& p);
// {"type":"breakup","seq":..,"breakup_id":..,"time_s":..,"time":..,"kind":"explosion","source":"scheduled",
//  "event_index":..,"parents":[..],"catastrophic":..,"specific_energy_j_per_g":..,"fragments":<count>,
//  "fragment_mass_kg":..,"first_id":..,"last_id":..,"remnant_id":..} (the fragments themselves: kessler
// fragments).
std::string breakup_json(std::uint64_t seq, const BreakupReport& b, const UtcEpoch& epoch);
// {"type":"launch","seq":..,"time_s":..,"time":..,"first_id":..,"last_id":..,"objects":..,"row":..} and
// the same keys (the object as first_id = last_id) for "end_of_life", "disposal" (with altitude_m),
// "disposal_failed" and "deorbit".
std::string lifecycle_json(std::uint64_t seq, const LifecycleReport& l, const UtcEpoch& epoch);
std::string checkpoint_json(std::uint64_t last_seq, std::int64_t step, const std::string& where);
// {"type":"summary","events":..,"collisions":..,"objects_final":..,"events_digest":..,"state_digest":..,...}
std::string summary_json(const RunSummary& s);

// Table rows for humans.
std::string encounter_row(std::uint64_t seq, const Encounter& e, const UtcEpoch& epoch,
                          const EncounterNames& names = {});
std::string burn_up_row(std::uint64_t seq, const BurnUp& b, const UtcEpoch& epoch);
std::string progress_row(const Progress& p);
std::string breakup_row(std::uint64_t seq, const BreakupReport& b, const UtcEpoch& epoch);
std::string lifecycle_row(std::uint64_t seq, const LifecycleReport& l, const UtcEpoch& epoch);
std::string summary_table(const RunSummary& s);

// The ingest report, before a run's events: {"type":"ingest","records":N,"kept":N,"dropped":{"<reason>":N}}
// and, for people, a few lines (records read, kept, each reason with its count).
std::string ingest_json(const IngestOutcome& ingest);
std::string ingest_table(const IngestOutcome& ingest);

const char* encounter_kind_name(EncounterKind kind);
const char* breakup_kind_name(BreakupKind kind);        // "collision", "explosion"
const char* breakup_source_name(BreakupSource source);  // "scheduled", "collision"
// "launch", "end_of_life", "disposal", "disposal_failed", "deorbit"
const char* lifecycle_kind_name(LifecycleEventKind kind);
// An object's name for listings: its name, else "FRAGMENT <id>" for a breakup's fragment, else empty.
std::string object_name(ObjectId id, const std::string& name);
std::string json_escape(const std::string& text);

}  // namespace kessler::cli
