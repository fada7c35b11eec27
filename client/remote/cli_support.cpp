#include "client/remote/cli_support.hpp"

#include <google/protobuf/util/json_util.h>

#include <cmath>
#include <cstdio>
#include <sstream>

#include "core/time/epoch.hpp"

namespace kessler::cli {

std::string unix_time_text(double unix_s) {
  if (unix_s <= 0) return "-";
  return UtcEpoch::from_calendar(1970, 1, 1, 0, 0, 0.0).plus_seconds(unix_s).to_iso8601(0);
}

std::string json_string(const std::string& s) {
  std::string out = "\"";
  for (unsigned char c : s) {
    switch (c) {
      case '"':
        out += "\\\"";
        break;
      case '\\':
        out += "\\\\";
        break;
      case '\n':
        out += "\\n";
        break;
      case '\r':
        out += "\\r";
        break;
      case '\t':
        out += "\\t";
        break;
      default:
        if (c < 0x20) {
          char buf[8];
          std::snprintf(buf, sizeof buf, "\\u%04x", c);
          out += buf;
        } else {
          out += static_cast<char>(c);
        }
    }
  }
  return out + "\"";
}

std::string json_number(double v) {
  if (!std::isfinite(v)) return "null";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

JsonObject& JsonObject::add(const std::string& key, const std::string& value) {
  return add_raw(key, json_string(value));
}
JsonObject& JsonObject::add(const std::string& key, double value) {
  return add_raw(key, json_number(value));
}
JsonObject& JsonObject::add(const std::string& key, std::int64_t value) {
  return add_raw(key, std::to_string(value));
}
JsonObject& JsonObject::add(const std::string& key, std::uint64_t value) {
  return add_raw(key, std::to_string(value));
}
JsonObject& JsonObject::add(const std::string& key, bool value) {
  return add_raw(key, value ? "true" : "false");
}
JsonObject& JsonObject::add_raw(const std::string& key, const std::string& json) {
  fields_.push_back(json_string(key) + ": " + json);
  return *this;
}
std::string JsonObject::str() const {
  std::string out = "{";
  for (std::size_t i = 0; i < fields_.size(); ++i) out += (i ? ", " : "") + fields_[i];
  return out + "}";
}

std::string to_json(const google::protobuf::Message& message) {
  std::string out;
  google::protobuf::util::JsonPrintOptions options;
  options.preserve_proto_field_names = true;
  options.always_print_primitive_fields = true;
  if (!google::protobuf::util::MessageToJsonString(message, &out, options).ok()) return "{}";
  return out;
}

const char* kind_name(v1::EncounterKind kind) {
  switch (kind) {
    case v1::ENCOUNTER_KIND_COLLISION:
      return "collision";
    case v1::ENCOUNTER_KIND_EVASION:
      return "evasion";
    default:
      return "conjunction";
  }
}

std::string summary_json(const v1::Run& run) {
  // The keys and order of `kessler run --local`'s summary line, with the run's id and state first.
  const v1::RunSummary& s = run.summary();
  const v1::PhaseTimers& t = s.timers();
  auto fixed6 = [](double v) {
    char buf[48];
    std::snprintf(buf, sizeof buf, "%.6f", v);
    return std::string(buf);
  };
  std::ostringstream o;
  o << "{\"type\":\"summary\",\"run_id\":" << run.id() << ",\"state\":\"" << v1::run_state_name(run.state())
    << "\",\"steps\":" << s.steps() << ",\"sim_time_s\":" << json_number(s.sim_time_s())
    << ",\"events\":" << s.events() << ",\"conjunctions\":" << s.conjunctions()
    << ",\"collisions\":" << s.collisions() << ",\"evasions\":" << s.evasions()
    << ",\"burn_ups\":" << s.burn_ups() << ",\"objects_initial\":" << s.objects_initial()
    << ",\"objects_final\":" << s.objects_final() << ",\"events_digest\":" << json_string(s.events_digest())
    << ",\"state_digest\":" << json_string(s.state_digest())
    << ",\"cancelled\":" << (s.cancelled() || run.state() == v1::RUN_STATE_CANCELLED ? "true" : "false")
    << ",\"timers_s\":{\"integrator\":" << fixed6(t.integrator_s())
    << ",\"burn_up\":" << fixed6(t.burn_up_s()) << ",\"grid\":" << fixed6(t.grid_s())
    << ",\"detection\":" << fixed6(t.detection_s()) << ",\"output\":" << fixed6(t.output_s())
    << ",\"checkpoint\":" << fixed6(t.checkpoint_s()) << ",\"total\":" << fixed6(t.total_s()) << "}";
  if (!run.error().empty()) o << ",\"error\":" << json_string(run.error());
  o << "}";
  return o.str();
}

std::string summary_text(const v1::Run& run) {
  const v1::RunSummary& s = run.summary();
  std::ostringstream out;
  out << "run " << run.id() << " " << v1::run_state_name(run.state());
  if (!run.error().empty()) out << ": " << run.error();
  out << "\n";
  if (run.has_summary()) {
    out << "  simulated     " << format_duration(s.sim_time_s()) << " in " << s.steps() << " steps, "
        << format_duration(s.timers().total_s()) << " wall\n";
    out << "  objects       " << s.objects_initial() << " -> " << s.objects_final() << " (" << s.burn_ups()
        << " burn-ups)\n";
    out << "  encounters    " << s.conjunctions() << " conjunctions, " << s.collisions() << " collisions, "
        << s.evasions() << " evasions\n";
    out << "  events        " << s.events() << ", digest " << s.events_digest() << "\n";
    out << "  final state   digest " << s.state_digest() << "\n";
  }
  return out.str();
}

BreakupReport breakup_report_of(const v1::Breakup& b) {
  BreakupReport out;
  out.breakup_id = b.breakup_id();
  out.source =
      b.source() == v1::BREAKUP_SOURCE_COLLISION ? BreakupSource::kCollision : BreakupSource::kScheduled;
  out.event_index = b.event_index();
  out.time_s = b.time_s();
  out.kind = b.kind() == v1::BREAKUP_KIND_COLLISION ? BreakupKind::kCollision : BreakupKind::kExplosion;
  out.parents.assign(b.parents().begin(), b.parents().end());
  out.catastrophic = b.catastrophic();
  out.specific_energy_j_per_g = b.specific_energy_j_per_g();
  out.fragment_count = b.fragment_count();
  out.fragment_mass_kg = b.fragment_mass_kg();
  out.first_id = b.first_id();
  out.last_id = b.last_id();
  out.remnant_id = b.remnant_id();
  return out;
}

LifecycleReport lifecycle_report_of(const v1::Lifecycle& l) {
  LifecycleReport out;
  // The wire's kinds have the core's numbers (server/run_manager.cpp); an unknown one reads as a launch.
  const int kind = static_cast<int>(l.kind());
  out.kind = kind >= 0 && kind <= static_cast<int>(LifecycleEventKind::kDeorbit)
                 ? static_cast<LifecycleEventKind>(kind)
                 : LifecycleEventKind::kLaunch;
  out.time_s = l.time_s();
  out.first_id = l.first_id();
  out.last_id = l.last_id();
  out.row = l.row();
  out.altitude_m = l.altitude_m();
  return out;
}

IngestOutcome ingest_outcome_of(const v1::IngestReport& report) {
  IngestOutcome out;
  out.records = report.records();
  out.kept = report.kept();
  for (const auto& drop : report.dropped()) out.dropped.push_back({drop.reason(), drop.count()});
  for (const auto& drag : report.drag()) out.drag.push_back({drag.reason(), drag.count()});
  return out;
}

std::string format_duration(double seconds) {
  if (!std::isfinite(seconds) || seconds < 0) return "?";
  auto total = static_cast<long long>(seconds + 0.5);
  long long d = total / 86400, h = total / 3600 % 24, m = total / 60 % 60, sec = total % 60;
  char buf[48];
  if (d > 0)
    std::snprintf(buf, sizeof buf, "%lldd %02lld:%02lld:%02lld", d, h, m, sec);
  else if (seconds < 60)
    std::snprintf(buf, sizeof buf, "%.1fs", seconds);
  else
    std::snprintf(buf, sizeof buf, "%02lld:%02lld:%02lld", h, m, sec);
  return buf;
}

std::string format_sim_time(const std::string& start_epoch, double sim_time_s) {
  auto epoch = UtcEpoch::parse_iso8601(start_epoch.empty() ? "2022-01-01T00:00:00Z" : start_epoch);
  if (!epoch) return json_number(sim_time_s) + " s";
  return epoch->plus_seconds(sim_time_s).to_iso8601(3);
}

std::string render_table(const std::vector<std::string>& header,
                         const std::vector<std::vector<std::string>>& rows) {
  std::vector<std::size_t> width(header.size(), 0);
  for (std::size_t i = 0; i < header.size(); ++i) width[i] = header[i].size();
  for (const auto& row : rows)
    for (std::size_t i = 0; i < row.size() && i < width.size(); ++i)
      width[i] = std::max(width[i], row[i].size());
  std::string out;
  auto line = [&](const std::vector<std::string>& cells) {
    std::string l;
    for (std::size_t i = 0; i < cells.size(); ++i) {
      l += cells[i];
      if (i + 1 < cells.size()) l += std::string(width[i] - cells[i].size() + 2, ' ');
    }
    out += l + "\n";
  };
  line(header);
  for (const auto& row : rows) line(row);
  return out;
}

std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string out = "\"";
  for (char c : s) out += c == '"' ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

std::string progress_percent(const v1::Progress& p) {
  if (p.total_steps() <= 0) return "-";
  char buf[16];
  std::snprintf(buf, sizeof buf, "%.1f%%",
                100.0 * static_cast<double>(p.step()) / static_cast<double>(p.total_steps()));
  return buf;
}

}  // namespace kessler::cli
