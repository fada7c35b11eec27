// What the remote commands share: JSON and table rendering, times and durations, and the
// run summary object (the same keys as `kessler run --local`).
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "core/scenario/run_builder.hpp"
#include "core/simulation/breakups.hpp"
#include "kessler/v1/names.hpp"
#include "kessler/v1/service.pb.h"

namespace kessler::cli {

// Minimal JSON building.
std::string json_string(const std::string& s);
// A daemon timestamp (seconds since 1970, UTC) as ISO 8601 to the second; "-" for none (0).
std::string unix_time_text(double unix_s);
std::string json_number(double v);
class JsonObject {
 public:
  JsonObject& add(const std::string& key, const std::string& value);  // a string
  JsonObject& add(const std::string& key, const char* value) { return add(key, std::string(value)); }
  JsonObject& add(const std::string& key, double value);
  JsonObject& add(const std::string& key, std::int64_t value);
  JsonObject& add(const std::string& key, std::uint64_t value);
  JsonObject& add(const std::string& key, bool value);
  JsonObject& add_raw(const std::string& key, const std::string& json);
  std::string str() const;

 private:
  std::vector<std::string> fields_;
};
// A message in the proto's canonical JSON mapping, on one line.
std::string to_json(const google::protobuf::Message& message);

const char* kind_name(v1::EncounterKind kind);

// The run's summary object on one line: the keys of `kessler run --local`'s summary ("type":
// "summary", steps, sim_time_s, events, conjunctions, collisions, evasions, burn_ups, objects_initial,
// objects_final, events_digest, state_digest, cancelled, timers_s) with run_id and state added.
std::string summary_json(const v1::Run& run);
// A few lines for people.
std::string summary_text(const v1::Run& run);

// The run's ingest report as `run --local` renders it (client/render.hpp).
IngestOutcome ingest_outcome_of(const v1::IngestReport& report);
// A breakup event in the core's terms (no fragment list), for render.hpp's breakup lines.
BreakupReport breakup_report_of(const v1::Breakup& breakup);
// A lifecycle event in the core's terms, for render.hpp's lifecycle lines.
LifecycleReport lifecycle_report_of(const v1::Lifecycle& event);
// A run's progress as "12.5%", or "-" before it knows its steps.
std::string progress_percent(const v1::Progress& p);

// "1d 02:03:04" style durations and UTC times of simulation seconds.
std::string format_duration(double seconds);
std::string format_sim_time(const std::string& start_epoch, double sim_time_s);

// Columns padded to their widest cell.
std::string render_table(const std::vector<std::string>& header,
                         const std::vector<std::vector<std::string>>& rows);
std::string csv_field(const std::string& s);

}  // namespace kessler::cli
