// The population section of `kessler show`: the figures' key numbers from the run's first and newest
// snapshots (objects by kind and status, median sizes and altitude, the spatial density's peak).
#include "client/commands/show_population.hpp"

#include <algorithm>
#include <cstdio>
#include <iostream>
#include <limits>

#include "client/remote/cli_support.hpp"
#include "core/physics/constants.hpp"
#include "core/simulation/snapshots.hpp"

namespace kessler::cli {
namespace {

// A snapshot's objects (every page), and its row; false when the call failed (nothing printed).
bool fetch(RemoteClient& client, std::int64_t run_id, std::int64_t step, v1::SnapshotInfo& info,
           std::vector<v1::SnapshotObject>& objects) {
  v1::GetSnapshotRequest request;
  request.set_run_id(run_id);
  request.set_step(step);
  request.set_page_size(100000);
  for (;;) {
    v1::GetSnapshotResponse response;
    if (!client.snapshot(request, response).ok) return false;
    info = response.snapshot();
    objects.insert(objects.end(), response.objects().begin(), response.objects().end());
    if (response.next_page_token().empty()) return true;
    request.set_page_token(response.next_page_token());
  }
}

double median_of(std::vector<double> v) {
  if (v.empty()) return 0.0;
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

// The column of one snapshot: counts, medians and the density peak, as text.
std::vector<std::string> column_of(const std::vector<v1::SnapshotObject>& objects) {
  std::uint64_t kinds[6] = {}, active = 0;
  std::vector<double> radius, mass, altitude;
  PopulationSnapshot orbits;
  orbits.resize(objects.size());
  for (std::size_t i = 0; i < objects.size(); ++i) {
    const auto& o = objects[i];
    ++kinds[std::clamp(static_cast<int>(o.kind()), 0, 5)];
    active += o.active();
    radius.push_back(o.radius_m());
    mass.push_back(o.mass_kg());
    altitude.push_back(o.semi_major_axis_km() - constants::kEarthEquatorialRadius_m / 1e3);
    orbits.semi_major_axis_m[i] = static_cast<float>(o.semi_major_axis_km() * 1e3);
    orbits.eccentricity[i] = static_cast<float>(o.eccentricity());
  }
  const DensityProfile density = spatial_density(orbits, 100.0, 2500.0);
  const double peak = density.peak_altitude_km();
  const auto shell = static_cast<std::size_t>((peak - density.first_altitude_km) / density.shell_km);
  char text[6][48];
  std::snprintf(text[0], 48, "%.3g", median_of(radius));
  std::snprintf(text[1], 48, "%.3g", median_of(mass));
  std::snprintf(text[2], 48, "%.0f", median_of(altitude));
  std::snprintf(text[3], 48, "%.0f", peak);
  std::snprintf(text[4], 48, "%.3g", density.objects_per_km3.empty() ? 0.0 : density.objects_per_km3[shell]);
  return {std::to_string(objects.size()),
          std::to_string(kinds[v1::OBJECT_KIND_PAYLOAD]),
          std::to_string(kinds[v1::OBJECT_KIND_ROCKET_BODY]),
          std::to_string(kinds[v1::OBJECT_KIND_DEBRIS]),
          std::to_string(kinds[v1::OBJECT_KIND_UNKNOWN]),
          std::to_string(kinds[v1::OBJECT_KIND_FRAGMENT]),
          std::to_string(active),
          std::to_string(objects.size() - active),
          text[0],
          text[1],
          text[2],
          text[3],
          text[4]};
}

}  // namespace

void print_population(RemoteClient& client, std::int64_t run_id) {
  v1::ListSnapshotsRequest list;
  list.set_run_id(run_id);
  list.set_page_size(1);
  v1::ListSnapshotsResponse first_page;
  if (!client.snapshots(list, first_page).ok || first_page.snapshots().empty()) return;
  v1::SnapshotInfo start, end;
  std::vector<v1::SnapshotObject> at_start, at_end;
  if (!fetch(client, run_id, first_page.snapshots(0).step(), start, at_start)) return;
  if (!fetch(client, run_id, std::numeric_limits<std::int64_t>::max(), end, at_end)) return;
  const std::vector<std::string> a = column_of(at_start), b = column_of(at_end);
  static const char* const names[] = {"objects",
                                      "  payload",
                                      "  rocket body",
                                      "  debris",
                                      "  unknown",
                                      "  fragments",
                                      "  active",
                                      "  passive",
                                      "median radius [m]",
                                      "median mass [kg]",
                                      "median altitude of a [km]",
                                      "density peak [km]",
                                      "  density there [objects/km^3]"};
  std::vector<std::vector<std::string>> rows;
  for (std::size_t k = 0; k < a.size(); ++k) rows.push_back({std::string("  ") + names[k], a[k], b[k]});
  std::cout << "\npopulation (" << first_page.total() << " snapshots)\n"
            << render_table({"", "START " + start.epoch(), "END " + end.epoch()}, rows);
}

}  // namespace kessler::cli
