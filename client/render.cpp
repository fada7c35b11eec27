#include "client/render.hpp"

#include <algorithm>
#include <cstdio>
#include <sstream>

namespace kessler::cli {
namespace {

std::string num(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

std::string fixed(double v, int decimals) {
  char buf[48];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  return buf;
}

std::string clock(double s) {
  long total = static_cast<long>(s + 0.5);
  char buf[32];
  std::snprintf(buf, sizeof buf, "%ld:%02ld:%02ld", total / 3600, (total / 60) % 60, total % 60);
  return buf;
}

std::string vector_json(const Eigen::Vector3d& v) {
  return "[" + num(v.x()) + "," + num(v.y()) + "," + num(v.z()) + "]";
}

}  // namespace

const char* encounter_kind_name(EncounterKind kind) {
  switch (kind) {
    case EncounterKind::kCollision:
      return "collision";
    case EncounterKind::kEvasion:
      return "evasion";
    default:
      return "conjunction";
  }
}

const char* breakup_kind_name(BreakupKind kind) {
  return kind == BreakupKind::kCollision ? "collision" : "explosion";
}

const char* breakup_source_name(BreakupSource source) {
  return source == BreakupSource::kCollision ? "collision" : "scheduled";
}

const char* lifecycle_kind_name(LifecycleEventKind kind) {
  switch (kind) {
    case LifecycleEventKind::kLaunch:
      return "launch";
    case LifecycleEventKind::kEndOfLife:
      return "end_of_life";
    case LifecycleEventKind::kDisposal:
      return "disposal";
    case LifecycleEventKind::kDisposalFailed:
      return "disposal_failed";
    case LifecycleEventKind::kDeorbit:
      return "deorbit";
  }
  return "lifecycle";
}

std::string object_name(ObjectId id, const std::string& name) {
  if (!name.empty() || id < kFirstFragmentId) return name;
  return "FRAGMENT " + std::to_string(id);
}

std::string json_escape(const std::string& text) {
  std::string out;
  for (char c : text) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\u%04x", c);
      out += buf;
    } else {
      out += c;
    }
  }
  return out;
}

std::string encounter_json(std::uint64_t seq, const Encounter& e, const UtcEpoch& epoch,
                           const EncounterNames& names) {
  std::ostringstream s;
  s << "{\"type\":\"" << encounter_kind_name(e.kind) << "\",\"seq\":" << seq << ",\"id1\":" << e.id1
    << ",\"id2\":" << e.id2 << ",\"name1\":\"" << json_escape(names.name1) << "\",\"name2\":\""
    << json_escape(names.name2) << "\",\"tca_s\":" << num(e.tca_s) << ",\"tca\":\""
    << epoch.plus_seconds(e.tca_s).to_iso8601(3) << "\",\"miss_distance_m\":" << num(e.miss_distance_m)
    << ",\"relative_speed_m_s\":" << num(e.relative_speed_m_s) << ",\"kappa\":" << num(e.kappa)
    << ",\"r1_m\":" << vector_json(e.r1_m) << ",\"v1_m_s\":" << vector_json(e.v1_m_s)
    << ",\"r2_m\":" << vector_json(e.r2_m) << ",\"v2_m_s\":" << vector_json(e.v2_m_s) << "}";
  return s.str();
}

std::string burn_up_json(std::uint64_t seq, const BurnUp& b, const UtcEpoch& epoch) {
  std::ostringstream s;
  s << "{\"type\":\"burn_up\",\"seq\":" << seq << ",\"id\":" << b.id << ",\"time_s\":" << num(b.time_s)
    << ",\"time\":\"" << epoch.plus_seconds(b.time_s).to_iso8601(3)
    << "\",\"altitude_m\":" << num(b.altitude_m) << "}";
  return s.str();
}

std::string progress_json(std::uint64_t seq, const Progress& p) {
  std::ostringstream s;
  s << "{\"type\":\"progress\",\"seq\":" << seq << ",\"step\":" << p.step
    << ",\"total_steps\":" << p.total_steps << ",\"sim_time_s\":" << num(p.sim_time_s)
    << ",\"objects_alive\":" << p.objects_alive
    << ",\"objects_by_type\":{\"payload\":" << p.objects_by_type.payload
    << ",\"rocket_body\":" << p.objects_by_type.rocket_body << ",\"debris\":" << p.objects_by_type.debris
    << ",\"unknown\":" << p.objects_by_type.unknown << ",\"fragments\":" << p.objects_by_type.fragments
    << "},\"events\":" << p.events_so_far << ",\"wall_s\":" << fixed(p.wall_s, 3)
    << ",\"eta_s\":" << fixed(p.eta_s, 3) << "}";
  return s.str();
}

std::string breakup_json(std::uint64_t seq, const BreakupReport& b, const UtcEpoch& epoch) {
  std::ostringstream s;
  s << "{\"type\":\"breakup\",\"seq\":" << seq << ",\"breakup_id\":" << b.breakup_id
    << ",\"time_s\":" << num(b.time_s) << ",\"time\":\"" << epoch.plus_seconds(b.time_s).to_iso8601(3)
    << "\",\"kind\":\"" << breakup_kind_name(b.kind) << "\",\"source\":\"" << breakup_source_name(b.source)
    << "\",\"event_index\":" << b.event_index << ",\"parents\":[";
  for (std::size_t i = 0; i < b.parents.size(); ++i) s << (i ? "," : "") << b.parents[i];
  s << "],\"catastrophic\":" << (b.catastrophic ? "true" : "false")
    << ",\"specific_energy_j_per_g\":" << num(b.specific_energy_j_per_g)
    << ",\"fragments\":" << b.fragment_count << ",\"fragment_mass_kg\":" << num(b.fragment_mass_kg)
    << ",\"first_id\":" << b.first_id << ",\"last_id\":" << b.last_id << ",\"remnant_id\":" << b.remnant_id
    << "}";
  return s.str();
}

std::string lifecycle_json(std::uint64_t seq, const LifecycleReport& l, const UtcEpoch& epoch) {
  std::ostringstream s;
  s << "{\"type\":\"" << lifecycle_kind_name(l.kind) << "\",\"seq\":" << seq
    << ",\"time_s\":" << num(l.time_s) << ",\"time\":\"" << epoch.plus_seconds(l.time_s).to_iso8601(3)
    << "\",\"first_id\":" << l.first_id << ",\"last_id\":" << l.last_id;
  if (l.kind == LifecycleEventKind::kLaunch)
    s << ",\"objects\":" << (l.last_id - l.first_id + 1) << ",\"row\":" << l.row;
  if (l.kind == LifecycleEventKind::kDisposal) s << ",\"altitude_m\":" << num(l.altitude_m);
  s << "}";
  return s.str();
}

std::string checkpoint_json(std::uint64_t last_seq, std::int64_t step, const std::string& where) {
  std::ostringstream s;
  s << "{\"type\":\"checkpoint\",\"step\":" << step << ",\"last_seq\":" << last_seq << ",\"path\":\""
    << json_escape(where) << "\"}";
  return s.str();
}

std::string summary_json(const RunSummary& r) {
  const PhaseTimers& t = r.timers;
  std::ostringstream s;
  s << "{\"type\":\"summary\",\"steps\":" << r.steps << ",\"sim_time_s\":" << num(r.sim_time_s)
    << ",\"events\":" << r.events << ",\"conjunctions\":" << r.conjunctions
    << ",\"collisions\":" << r.collisions << ",\"evasions\":" << r.evasions << ",\"burn_ups\":" << r.burn_ups
    << ",\"objects_initial\":" << r.objects_initial << ",\"objects_final\":" << r.objects_final
    << ",\"events_digest\":\"" << r.events_digest << "\",\"state_digest\":\"" << r.state_digest
    << "\",\"cancelled\":" << (r.cancelled ? "true" : "false")
    << ",\"timers_s\":{\"integrator\":" << fixed(t.integrator_s, 6)
    << ",\"burn_up\":" << fixed(t.burn_up_s, 6) << ",\"grid\":" << fixed(t.grid_s, 6)
    << ",\"detection\":" << fixed(t.detection_s, 6) << ",\"output\":" << fixed(t.output_s, 6)
    << ",\"checkpoint\":" << fixed(t.checkpoint_s, 6) << ",\"total\":" << fixed(t.total_s, 6) << "}}";
  return s.str();
}

std::string ingest_json(const IngestOutcome& ingest) {
  std::ostringstream s;
  s << "{\"type\":\"ingest\",\"records\":" << ingest.records << ",\"kept\":" << ingest.kept
    << ",\"dropped\":{";
  for (std::size_t i = 0; i < ingest.dropped.size(); ++i)
    s << (i ? "," : "") << "\"" << json_escape(ingest.dropped[i].first) << "\":" << ingest.dropped[i].second;
  s << "}";
  if (!ingest.drag.empty()) {
    s << ",\"drag\":{";
    for (std::size_t i = 0; i < ingest.drag.size(); ++i)
      s << (i ? "," : "") << "\"" << json_escape(ingest.drag[i].first) << "\":" << ingest.drag[i].second;
    s << "}";
  }
  s << "}";
  return s.str();
}

std::string ingest_table(const IngestOutcome& ingest) {
  std::uint64_t dropped = 0;
  std::size_t width = 0;
  for (const auto& [reason, count] : ingest.dropped) {
    dropped += count;
    width = std::max(width, reason.size());
  }
  std::ostringstream s;
  s << "ingest: " << ingest.records << " records read, " << ingest.kept << " kept, " << dropped
    << " dropped\n";
  for (const auto& [reason, count] : ingest.dropped)
    s << "  " << reason << std::string(width - reason.size() + 2, ' ') << count << "\n";
  if (!ingest.drag.empty()) {
    s << "drag (Cd A/m) of the kept objects:\n";
    for (const auto& [source, count] : ingest.drag) s << "  " << source << ": " << count << "\n";
  }
  return s.str();
}

std::string encounter_row(std::uint64_t seq, const Encounter& e, const UtcEpoch& epoch,
                          const EncounterNames& names) {
  char buf[384];
  std::snprintf(
      buf, sizeof buf, "%8llu  %-11s  %8llu %-20.20s  %8llu %-20.20s  %s  %12.3f m  %9.1f m/s  kappa %.3f",
      static_cast<unsigned long long>(seq), encounter_kind_name(e.kind),
      static_cast<unsigned long long>(e.id1), names.name1.empty() ? "-" : names.name1.c_str(),
      static_cast<unsigned long long>(e.id2), names.name2.empty() ? "-" : names.name2.c_str(),
      epoch.plus_seconds(e.tca_s).to_iso8601(3).c_str(), e.miss_distance_m, e.relative_speed_m_s, e.kappa);
  return buf;
}

std::string burn_up_row(std::uint64_t seq, const BurnUp& b, const UtcEpoch& epoch) {
  char buf[256];
  std::snprintf(buf, sizeof buf, "%8llu  %-11s  %8llu  %8s  %s  %12.3f km",
                static_cast<unsigned long long>(seq), "burn_up", static_cast<unsigned long long>(b.id), "",
                epoch.plus_seconds(b.time_s).to_iso8601(3).c_str(), b.altitude_m / 1e3);
  return buf;
}

std::string breakup_row(std::uint64_t seq, const BreakupReport& b, const UtcEpoch& epoch) {
  std::string parents;
  for (ObjectId id : b.parents) {
    if (!parents.empty()) parents += '+';
    parents += std::to_string(id);
  }
  char buf[384];
  std::snprintf(buf, sizeof buf, "%8llu  %-11s  #%u %s (%s) of %s  %s  %llu fragments %llu-%llu  %.1f kg%s",
                static_cast<unsigned long long>(seq), "breakup", static_cast<unsigned>(b.breakup_id),
                breakup_kind_name(b.kind), breakup_source_name(b.source), parents.c_str(),
                epoch.plus_seconds(b.time_s).to_iso8601(3).c_str(),
                static_cast<unsigned long long>(b.fragment_count),
                static_cast<unsigned long long>(b.first_id), static_cast<unsigned long long>(b.last_id),
                b.fragment_mass_kg, b.catastrophic ? "  catastrophic" : "");
  return buf;
}

std::string lifecycle_row(std::uint64_t seq, const LifecycleReport& l, const UtcEpoch& epoch) {
  const std::string when = epoch.plus_seconds(l.time_s).to_iso8601(3);
  const auto first = static_cast<unsigned long long>(l.first_id),
             last = static_cast<unsigned long long>(l.last_id);
  char buf[256];
  if (l.kind == LifecycleEventKind::kLaunch)
    std::snprintf(buf, sizeof buf, "%8llu  %-11s  %llu objects %llu-%llu  %s  plan row %llu",
                  static_cast<unsigned long long>(seq), "launch", last - first + 1, first, last, when.c_str(),
                  static_cast<unsigned long long>(l.row));
  else if (l.kind == LifecycleEventKind::kDisposal)
    std::snprintf(buf, sizeof buf, "%8llu  %-11s  %8llu  %s  %12.3f km", static_cast<unsigned long long>(seq),
                  "disposal", first, when.c_str(), l.altitude_m / 1e3);
  else
    std::snprintf(buf, sizeof buf, "%8llu  %-11s  %8llu  %s", static_cast<unsigned long long>(seq),
                  lifecycle_kind_name(l.kind), first, when.c_str());
  return buf;
}

std::string progress_row(const Progress& p) {
  char buf[256];
  const double pct =
      p.total_steps > 0 ? 100.0 * static_cast<double>(p.step) / static_cast<double>(p.total_steps) : 0;
  std::snprintf(buf, sizeof buf,
                "progress  step %lld/%lld (%5.1f%%)  sim %.1f d  objects %llu  events %llu  wall %s  eta %s",
                static_cast<long long>(p.step), static_cast<long long>(p.total_steps), pct,
                p.sim_time_s / 86400.0, static_cast<unsigned long long>(p.objects_alive),
                static_cast<unsigned long long>(p.events_so_far), clock(p.wall_s).c_str(),
                clock(p.eta_s).c_str());
  return buf;
}

std::string summary_table(const RunSummary& r) {
  const PhaseTimers& t = r.timers;
  std::ostringstream s;
  s << (r.cancelled ? "run stopped early\n" : "run finished\n");
  s << "  steps          " << r.steps << " (" << fixed(r.sim_time_s / 86400.0, 3) << " days)\n";
  s << "  objects        " << r.objects_initial << " -> " << r.objects_final << "\n";
  s << "  events         " << r.events << " (conjunctions " << r.conjunctions << ", collisions "
    << r.collisions << ", evasions " << r.evasions << ", burn-ups " << r.burn_ups << ")\n";
  s << "  events_digest  " << r.events_digest << "\n";
  s << "  state_digest   " << r.state_digest << "\n";
  s << "  time [s]       integrator " << fixed(t.integrator_s, 3) << ", burn-up " << fixed(t.burn_up_s, 3)
    << ", grid " << fixed(t.grid_s, 3) << ", detection " << fixed(t.detection_s, 3) << ", output "
    << fixed(t.output_s, 3) << ", checkpoint " << fixed(t.checkpoint_s, 3) << ", total "
    << fixed(t.total_s, 3) << "\n";
  return s.str();
}

}  // namespace kessler::cli
