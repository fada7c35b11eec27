// kessler snapshot RUN: a run's population at a snapshot (scenario snapshots.every_days): every object's
// kind, status, size and osculating elements, filtered by kind, radius and altitude band; or, with
// --list, the run's snapshots.
#include <cstdio>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "client/command.hpp"
#include "client/remote/cli_support.hpp"
#include "client/remote/remote_client.hpp"

namespace kessler::cli {
namespace {

struct SnapshotOptions {
  std::int64_t run_id = 0;
  std::string at;  // ISO 8601 epoch
  std::optional<std::int64_t> step;
  std::vector<std::string> kinds;
  std::optional<double> min_radius_m, max_radius_m, min_altitude_km, max_altitude_km;
  bool list = false;
};

const char* kind_text(v1::ObjectKind kind) {
  switch (kind) {
    case v1::OBJECT_KIND_PAYLOAD:
      return "payload";
    case v1::OBJECT_KIND_ROCKET_BODY:
      return "rocket_body";
    case v1::OBJECT_KIND_DEBRIS:
      return "debris";
    case v1::OBJECT_KIND_FRAGMENT:
      return "fragment";
    default:
      return "unknown";
  }
}

std::optional<v1::ObjectKind> kind_of(const std::string& text) {
  for (v1::ObjectKind k : {v1::OBJECT_KIND_PAYLOAD, v1::OBJECT_KIND_ROCKET_BODY, v1::OBJECT_KIND_DEBRIS,
                           v1::OBJECT_KIND_UNKNOWN, v1::OBJECT_KIND_FRAGMENT})
    if (text == kind_text(k)) return k;
  return std::nullopt;
}

const char* const kColumns =
    "id,kind,active,radius_m,mass_kg,semi_major_axis_km,eccentricity,inclination_deg,raan_deg,"
    "argument_of_perigee_deg,mean_anomaly_deg,perigee_altitude_km,apogee_altitude_km";

std::vector<double> numbers_of(const v1::SnapshotObject& o) {
  return {o.radius_m(),
          o.mass_kg(),
          o.semi_major_axis_km(),
          o.eccentricity(),
          o.inclination_deg(),
          o.raan_deg(),
          o.argument_of_perigee_deg(),
          o.mean_anomaly_deg(),
          o.perigee_altitude_km(),
          o.apogee_altitude_km()};
}

void print_objects(const v1::SnapshotInfo& info, const std::vector<v1::SnapshotObject>& rows,
                   OutputFormat format) {
  if (format == OutputFormat::kJson) {
    std::cout << "{\"step\":" << info.step() << ",\"sim_time_s\":" << json_number(info.sim_time_s())
              << ",\"epoch\":" << json_string(info.epoch()) << ",\"objects\":[";
    static const char* const keys[] = {"radius_m",
                                       "mass_kg",
                                       "semi_major_axis_km",
                                       "eccentricity",
                                       "inclination_deg",
                                       "raan_deg",
                                       "argument_of_perigee_deg",
                                       "mean_anomaly_deg",
                                       "perigee_altitude_km",
                                       "apogee_altitude_km"};
    for (std::size_t i = 0; i < rows.size(); ++i) {
      JsonObject obj;
      obj.add("id", static_cast<std::uint64_t>(rows[i].id())).add("kind", kind_text(rows[i].kind()));
      obj.add("active", rows[i].active());
      const std::vector<double> v = numbers_of(rows[i]);
      for (std::size_t k = 0; k < v.size(); ++k) obj.add(keys[k], v[k]);
      std::cout << (i ? ",\n " : "") << obj.str();
    }
    std::cout << "]}\n";
    return;
  }
  std::cout << kColumns << "\n";
  for (const auto& o : rows) {
    std::cout << o.id() << "," << kind_text(o.kind()) << "," << (o.active() ? "true" : "false");
    for (double v : numbers_of(o)) std::cout << "," << json_number(v);
    std::cout << "\n";
  }
}

int list_snapshots(const SnapshotOptions& o, RemoteClient& client, OutputFormat format) {
  v1::ListSnapshotsRequest request;
  request.set_run_id(o.run_id);
  std::vector<v1::SnapshotInfo> rows;
  for (;;) {
    v1::ListSnapshotsResponse response;
    const CallResult r = client.snapshots(request, response);
    if (!r.ok) {
      std::cerr << "kessler snapshot: " << r.describe() << "\n";
      return r.exit_code();
    }
    rows.insert(rows.end(), response.snapshots().begin(), response.snapshots().end());
    if (response.next_page_token().empty()) break;
    request.set_page_token(response.next_page_token());
  }
  if (format == OutputFormat::kJson) {
    std::cout << "[";
    for (std::size_t i = 0; i < rows.size(); ++i) std::cout << (i ? ",\n " : "") << to_json(rows[i]);
    std::cout << "]\n";
    return kExitOk;
  }
  std::cout << "step,sim_time_s,epoch,objects,stored_bytes\n";
  for (const auto& s : rows)
    std::cout << s.step() << "," << json_number(s.sim_time_s()) << "," << s.epoch() << "," << s.objects()
              << "," << s.stored_bytes() << "\n";
  return kExitOk;
}

int show_snapshot(const SnapshotOptions& o, const GlobalOptions& global) {
  OutputFormat format;
  if (!resolve_output("snapshot", global.output.empty() ? "csv" : global.output, {"csv", "json"}, format))
    return kExitUsage;
  if (o.step && !o.at.empty()) return usage_error("snapshot", "--at and --step: give one of them");
  RemoteClient client(server_address(global.server));
  if (o.list) return list_snapshots(o, client, format);
  v1::GetSnapshotRequest request;
  request.set_run_id(o.run_id);
  if (o.step) request.set_step(*o.step);
  if (!o.at.empty()) request.set_epoch(o.at);
  for (const std::string& k : o.kinds) {
    const auto kind = kind_of(k);
    if (!kind)
      return usage_error(
          "snapshot", "--kind: unknown kind '" + k + "' (payload, rocket_body, debris, unknown, fragment)");
    request.add_kinds(*kind);
  }
  if (o.min_radius_m) request.set_min_radius_m(*o.min_radius_m);
  if (o.max_radius_m) request.set_max_radius_m(*o.max_radius_m);
  if (o.min_altitude_km) request.set_min_altitude_km(*o.min_altitude_km);
  if (o.max_altitude_km) request.set_max_altitude_km(*o.max_altitude_km);
  request.set_page_size(50000);
  std::vector<v1::SnapshotObject> rows;
  v1::SnapshotInfo info;
  for (;;) {
    v1::GetSnapshotResponse response;
    const CallResult r = client.snapshot(request, response);
    if (!r.ok) {
      std::cerr << "kessler snapshot: " << r.describe() << "\n";
      return r.exit_code();
    }
    info = response.snapshot();
    rows.insert(rows.end(), response.objects().begin(), response.objects().end());
    if (response.next_page_token().empty()) break;
    // Pages of one snapshot: pin its step so a snapshot stored meanwhile cannot change the page.
    request.set_step(info.step());
    request.set_page_token(response.next_page_token());
  }
  print_objects(info, rows, format);
  return kExitOk;
}

}  // namespace

CommandRun setup_snapshot(CLI::App& command, GlobalOptions& global) {
  auto o = std::make_shared<SnapshotOptions>();
  add_run_id(command, o->run_id);
  command
      .add_option("--at", o->at,
                  "the last snapshot at or before this epoch (ISO 8601 UTC); default the newest")
      ->option_text("EPOCH");
  command.add_option("--step", o->step, "the last snapshot at or before this step")->option_text("N");
  command
      .add_option("--kind", o->kinds,
                  "only objects of this kind (repeatable): payload, rocket_body, debris, "
                  "unknown, fragment")
      ->option_text("KIND");
  command.add_option("--min-radius-m", o->min_radius_m, "only objects with a radius of at least this [m]");
  command.add_option("--max-radius-m", o->max_radius_m, "only objects with a radius of at most this [m]");
  command.add_option("--min-altitude-km", o->min_altitude_km,
                     "only orbits whose apogee reaches this altitude [km]");
  command.add_option("--max-altitude-km", o->max_altitude_km,
                     "only orbits whose perigee is at most this altitude [km]");
  command.add_flag("--list", o->list, "list the run's snapshots (step, epoch, objects, stored size) instead");
  add_global_options(command, global,
                     "csv (default: a header row, then one row per object) or json (one object with the "
                     "snapshot's step, time, epoch and an array of objects with the CSV's columns as keys)");
  command.footer(
      "Prints a run's population at one of its snapshots (the scenario's snapshots.every_days): per object "
      "its id, kind, status, radius, mass and osculating elements in the TEME frame of the scenario epoch "
      "(angles in degrees), with perigee and apogee altitudes.\n\n"
      "examples:\n"
      "  kessler snapshot 3 --list\n"
      "  kessler snapshot 3 --at 2023-01-01T00:00:00Z --kind fragment --output csv > fragments.csv\n"
      "  kessler snapshot 3 --min-altitude-km 700 --max-altitude-km 900 --output json");
  return [o, &global] { return show_snapshot(*o, global); };
}

}  // namespace kessler::cli
