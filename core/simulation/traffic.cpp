#include "core/simulation/traffic.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>

#include "core/physics/atmosphere.hpp"
#include "core/physics/constants.hpp"
#include "core/random/counter_random.hpp"

namespace kessler {

std::int64_t launch_boundary_step(double epoch_offset_s, double dt_s) {
  // The same rounding as the scheduled breakups: an offset of k dt lands on boundary k.
  const double steps = std::ceil(epoch_offset_s / dt_s * (1.0 - 1e-12));
  return std::max<std::int64_t>(1, static_cast<std::int64_t>(steps));
}

std::optional<std::int64_t> next_traffic_step(const TrafficSettings& settings, const TrafficState& state,
                                              std::int64_t step, double dt_s) {
  std::optional<std::int64_t> next;
  if (!settings.enabled) return next;
  auto consider = [&](std::int64_t k) {
    k = std::max(k, step + 1);
    if (!next || k < *next) next = k;
  };
  if (state.next_launch < settings.launches.size())
    consider(launch_boundary_step(settings.launches[state.next_launch].epoch_offset_s, dt_s));
  if (!state.active.empty()) consider(launch_boundary_step(state.active.front().end_of_life_s, dt_s));
  return next;
}

namespace {

ObjectRecord launched_record(const PlannedObject& o, ObjectId id, double t_s) {
  ObjectRecord r;
  r.id = id;
  const OrbitElements el = advance(o.elements, t_s - o.epoch_offset_s);
  state_from_elements(el, r.position_m, r.velocity_m_s);
  r.radius_m = o.radius_m;
  r.mass_kg = o.mass_kg;
  // Drag and SRP area-to-mass of a sphere of the radius (Cd 2.2), as the catalog's sized objects.
  const double area = M_PI * o.radius_m * o.radius_m;
  r.drag_area_to_mass_m2_kg = constants::kDefaultDragCoefficient * area / o.mass_kg;
  r.srp_area_to_mass_m2_kg = area / o.mass_kg;
  r.type = o.type;
  r.status = o.lifetime_s > 0.0 ? ObjectStatus::kActive : ObjectStatus::kPassive;
  return r;
}

bool by_end(const ActiveLife& a, const ActiveLife& b) {
  return a.end_of_life_s != b.end_of_life_s ? a.end_of_life_s < b.end_of_life_s : a.id < b.id;
}

}  // namespace

void adopt_catalog_actives(const TrafficSettings& settings, std::uint64_t seed, Population& population,
                           TrafficState& state) {
  if (!settings.enabled || !(settings.catalog_active_lifetime_years > 0.0)) return;
  const double span_s = settings.catalog_active_lifetime_years * 365.25 * 86400.0;
  for (std::size_t i = 0; i < population.size(); ++i) {
    if (population.status[i] != ObjectStatus::kActive || population.type[i] != ObjectType::kPayload) continue;
    const ObjectId id = population.id[i];
    const double end_s = span_s * random_uniform(seed, id, RandomPurpose::kRemainingLifetime, 0);
    const ActiveLife life{id, end_s, population.drag_area_to_mass_m2_kg[i], true};
    population.drag_area_to_mass_m2_kg[i] = 0.0;
    state.active.insert(std::upper_bound(state.active.begin(), state.active.end(), life, by_end), life);
  }
}

std::vector<LifecycleReport> launch_due(const TrafficSettings& settings, std::int64_t step, double dt_s,
                                        Population& population, TrafficState& state) {
  std::vector<LifecycleReport> out;
  if (!settings.enabled) return out;
  const double t_s = static_cast<double>(step) * dt_s;
  while (state.next_launch < settings.launches.size() &&
         launch_boundary_step(settings.launches[state.next_launch].epoch_offset_s, dt_s) <= step) {
    const std::uint64_t k = state.next_launch++;
    const PlannedObject& o = settings.launches[k];
    const ObjectId id = kFirstLaunchId + k;
    ObjectRecord r = launched_record(o, id, t_s);
    if (o.lifetime_s > 0.0) {
      ActiveLife life{id, o.epoch_offset_s + o.lifetime_s, r.drag_area_to_mass_m2_kg, o.manoeuvres};
      if (o.manoeuvres) r.drag_area_to_mass_m2_kg = 0.0;
      state.active.insert(std::upper_bound(state.active.begin(), state.active.end(), life, by_end), life);
    }
    population.add(r);
    if (!out.empty() && out.back().row == o.row && out.back().last_id + 1 == id) {
      out.back().last_id = id;
    } else {
      LifecycleReport report;
      report.kind = LifecycleEventKind::kLaunch;
      report.time_s = t_s;
      report.first_id = report.last_id = id;
      report.row = o.row;
      out.push_back(report);
    }
  }
  return out;
}

std::vector<LifecycleReport> retire_due(const TrafficSettings& settings, std::uint64_t seed, double time_s,
                                        double burn_up_altitude_m, Population& population,
                                        TrafficState& state) {
  std::vector<LifecycleReport> out;
  if (!settings.enabled) return out;
  std::vector<char> leaving;
  std::size_t done = 0;
  for (; done < state.active.size() && state.active[done].end_of_life_s <= time_s; ++done) {
    const ActiveLife& life = state.active[done];
    const std::optional<std::size_t> at = population.index_of(life.id);
    if (!at) continue;
    const std::size_t i = *at;
    population.status[i] = ObjectStatus::kPassive;
    population.drag_area_to_mass_m2_kg[i] = life.drag_area_to_mass_m2_kg;
    LifecycleReport report;
    report.time_s = time_s;
    report.first_id = report.last_id = life.id;
    report.kind = LifecycleEventKind::kEndOfLife;
    out.push_back(report);
    if (!disposal_succeeds(seed, life.id, settings.disposal.success_probability)) {
      report.kind = LifecycleEventKind::kDisposalFailed;
      out.push_back(report);
      continue;
    }
    if (settings.disposal.deorbit) {
      report.kind = LifecycleEventKind::kDeorbit;
      if (leaving.empty()) leaving.assign(population.size(), 0);
      leaving[i] = 1;
      out.push_back(report);
      continue;
    }
    Eigen::Vector3d r = population.state.position(i), v = population.state.velocity(i);
    const Eigen::Vector3d h = r.cross(v);
    const double inclination = std::acos(std::clamp(h.z() / h.norm(), -1.0, 1.0));
    const double now_m = r.norm() - constants::kEarthEquatorialRadius_m;
    const double altitude = disposal_altitude_m(settings.disposal.target_lifetime_years, inclination,
                                                life.drag_area_to_mass_m2_kg, burn_up_altitude_m, now_m,
                                                DensityTable::standard());
    // Already low enough: it stays on its orbit.
    if (altitude < now_m) {
      move_to_circular_orbit(constants::kEarthEquatorialRadius_m + altitude, r, v);
      population.state.set(i, r, v);
    }
    report.kind = LifecycleEventKind::kDisposal;
    report.altitude_m = altitude;
    out.push_back(report);
  }
  state.active.erase(state.active.begin(), state.active.begin() + static_cast<std::ptrdiff_t>(done));
  if (!leaving.empty()) population.remove_flagged(leaving);
  return out;
}

}  // namespace kessler
