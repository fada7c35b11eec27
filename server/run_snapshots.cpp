// The run manager's snapshot queries (ListSnapshots, GetSnapshot) and the read path the figures take.
#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/physics/constants.hpp"
#include "core/scenario/run_builder.hpp"
#include "server/run_manager.hpp"

namespace kessler::server {

namespace {

using Code = ServiceError::Code;

constexpr double kDegPerRad = 180.0 / std::numbers::pi;

v1::ObjectKind to_proto(ObjectKind kind) {
  switch (kind) {
    case ObjectKind::kPayload:
      return v1::OBJECT_KIND_PAYLOAD;
    case ObjectKind::kRocketBody:
      return v1::OBJECT_KIND_ROCKET_BODY;
    case ObjectKind::kDebris:
      return v1::OBJECT_KIND_DEBRIS;
    case ObjectKind::kFragment:
      return v1::OBJECT_KIND_FRAGMENT;
    case ObjectKind::kUnknown:
      break;
  }
  return v1::OBJECT_KIND_UNKNOWN;
}

v1::SnapshotInfo info_of(const StoredSnapshotInfo& row, const UtcEpoch& start) {
  v1::SnapshotInfo info;
  info.set_step(row.step);
  info.set_sim_time_s(row.sim_time_s);
  info.set_epoch(start.plus_seconds(row.sim_time_s).to_iso8601());
  info.set_objects(row.objects);
  info.set_stored_bytes(row.stored_bytes);
  return info;
}

v1::SnapshotObject object_of(const PopulationSnapshot& s, std::size_t i) {
  v1::SnapshotObject o;
  o.set_id(s.id[i]);
  o.set_kind(to_proto(kind_of(s.id[i], s.type[i])));
  o.set_active(s.status[i] == ObjectStatus::kActive);
  o.set_radius_m(s.radius_m[i]);
  o.set_mass_kg(s.mass_kg[i]);
  const double a_km = s.semi_major_axis_m[i] / 1e3, e = s.eccentricity[i];
  o.set_semi_major_axis_km(a_km);
  o.set_eccentricity(e);
  o.set_inclination_deg(s.inclination_rad[i] * kDegPerRad);
  o.set_raan_deg(s.raan_rad[i] * kDegPerRad);
  o.set_argument_of_perigee_deg(s.argument_of_perigee_rad[i] * kDegPerRad);
  o.set_mean_anomaly_deg(s.mean_anomaly_rad[i] * kDegPerRad);
  const double radius_km = constants::kEarthEquatorialRadius_m / 1e3;
  o.set_perigee_altitude_km(a_km * (1.0 - e) - radius_km);
  o.set_apogee_altitude_km(a_km * (1.0 + e) - radius_km);
  return o;
}

bool matches(const v1::GetSnapshotRequest& r, const v1::SnapshotObject& o) {
  if (r.kinds_size() > 0 && std::find(r.kinds().begin(), r.kinds().end(), o.kind()) == r.kinds().end())
    return false;
  if (r.has_min_radius_m() && o.radius_m() < r.min_radius_m()) return false;
  if (r.has_max_radius_m() && o.radius_m() > r.max_radius_m()) return false;
  if (r.has_min_altitude_km() && o.apogee_altitude_km() < r.min_altitude_km()) return false;
  if (r.has_max_altitude_km() && o.perigee_altitude_km() > r.max_altitude_km()) return false;
  return true;
}

void check_request(const v1::GetSnapshotRequest& r) {
  if (r.page_size() < 0) throw ServiceError(Code::kInvalidArgument, "page_size: must be >= 0", "page_size");
  for (int k : r.kinds())
    if (!v1::ObjectKind_IsValid(k) || k == v1::OBJECT_KIND_UNSPECIFIED)
      throw ServiceError(Code::kInvalidArgument, "kinds: unknown kind " + std::to_string(k), "kinds");
  for (auto [has, value, path] :
       {std::tuple{r.has_min_radius_m(), r.min_radius_m(), "min_radius_m"},
        std::tuple{r.has_max_radius_m(), r.max_radius_m(), "max_radius_m"},
        std::tuple{r.has_min_altitude_km(), r.min_altitude_km(), "min_altitude_km"},
        std::tuple{r.has_max_altitude_km(), r.max_altitude_km(), "max_altitude_km"}})
    if (has && !std::isfinite(value))
      throw ServiceError(Code::kInvalidArgument, std::string(path) + ": must be a finite number", path);
}

}  // namespace

UtcEpoch RunManager::start_epoch(const v1::Run& run) {
  return to_simulation_config(run.scenario(), 0).start_epoch;
}

std::optional<std::int64_t> RunManager::snapshot_step(const v1::Run& run, const v1::GetSnapshotRequest& r) {
  const v1::Scenario& s = run.scenario();
  const double dt_s = s.has_dt_s() ? s.dt_s() : to_simulation_config(s, 0).dt_s;
  switch (r.at_case()) {
    case v1::GetSnapshotRequest::kStep:
      return r.step();
    case v1::GetSnapshotRequest::kSimTimeS:
      if (!std::isfinite(r.sim_time_s()))
        throw ServiceError(Code::kInvalidArgument, "sim_time_s: must be a finite number", "sim_time_s");
      return static_cast<std::int64_t>(std::floor(r.sim_time_s() / dt_s * (1.0 + 1e-12)));
    case v1::GetSnapshotRequest::kEpoch: {
      std::string why;
      const auto epoch = UtcEpoch::parse_iso8601(r.epoch(), &why);
      if (!epoch) throw ServiceError(Code::kInvalidArgument, "epoch: " + why, "epoch");
      return static_cast<std::int64_t>(
          std::floor(epoch->seconds_since(start_epoch(run)) / dt_s * (1.0 + 1e-12)));
    }
    case v1::GetSnapshotRequest::AT_NOT_SET:
      break;
  }
  return std::nullopt;
}

v1::ListSnapshotsResponse RunManager::list_snapshots(const v1::ListSnapshotsRequest& request) {
  const v1::Run run = get(request.run_id(), true);  // NOT_FOUND
  if (request.page_size() < 0)
    throw ServiceError(Code::kInvalidArgument, "page_size: must be >= 0", "page_size");
  Page<StoredSnapshotInfo> page;
  try {
    page = store_.list_snapshots(request.run_id(), request.page_size(), request.page_token());
  } catch (const std::invalid_argument& e) {
    throw ServiceError(Code::kInvalidArgument, e.what(), "page_token");
  }
  const UtcEpoch start = start_epoch(run);
  v1::ListSnapshotsResponse response;
  for (const auto& row : page.items) *response.add_snapshots() = info_of(row, start);
  response.set_next_page_token(page.next_token);
  response.set_total(page.total);
  return response;
}

v1::GetSnapshotResponse RunManager::get_snapshot(const v1::GetSnapshotRequest& request) {
  const v1::Run run = get(request.run_id(), true);  // NOT_FOUND
  check_request(request);
  const std::optional<std::int64_t> step = snapshot_step(run, request);
  std::size_t offset = 0;
  if (!request.page_token().empty()) {
    std::size_t used = 0;
    try {
      offset = std::stoull(request.page_token(), &used);
    } catch (...) {
      used = 0;
    }
    if (used != request.page_token().size())
      throw ServiceError(Code::kInvalidArgument, "page_token: not a token from a previous page",
                         "page_token");
  }
  const auto info = store_.snapshot_info(request.run_id(), step);
  if (!info)
    throw ServiceError(Code::kNotFound, "run " + std::to_string(request.run_id()) + " has no snapshot" +
                                            (step ? " at or before step " + std::to_string(*step) : ""));
  const PopulationSnapshot snapshot = *store_.read_snapshot(request.run_id(), info->step);
  const std::size_t page_size =
      request.page_size() == 0 ? 1000 : static_cast<std::size_t>(std::min(request.page_size(), 100000));
  v1::GetSnapshotResponse response;
  *response.mutable_snapshot() = info_of(*info, start_epoch(run));
  std::uint64_t total = 0;
  for (std::size_t i = 0; i < snapshot.size(); ++i) {
    v1::SnapshotObject o = object_of(snapshot, i);
    if (!matches(request, o)) continue;
    if (total >= offset && static_cast<std::size_t>(response.objects_size()) < page_size)
      *response.add_objects() = std::move(o);
    ++total;
  }
  response.set_total(total);
  if (offset + page_size < total) response.set_next_page_token(std::to_string(offset + page_size));
  return response;
}

std::optional<PopulationSnapshot> RunManager::population_snapshot(std::int64_t run_id,
                                                                  std::optional<std::int64_t> step) {
  get(run_id, false);  // NOT_FOUND
  return store_.read_snapshot(run_id, step);
}

std::vector<StoredSnapshotInfo> RunManager::snapshot_steps(std::int64_t run_id) {
  get(run_id, false);  // NOT_FOUND
  std::vector<StoredSnapshotInfo> all;
  std::string token;
  do {
    Page<StoredSnapshotInfo> page = store_.list_snapshots(run_id, 100000, token);
    all.insert(all.end(), page.items.begin(), page.items.end());
    token = page.next_token;
  } while (!token.empty());
  return all;
}

}  // namespace kessler::server
