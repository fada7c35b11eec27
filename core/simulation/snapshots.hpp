// Population snapshots: the whole population at a step boundary, compact, for the figures (population
// distributions, spatial density, Gabbard diagrams) and for GetSnapshot.
//
// A snapshot is derived from the population the events and the state digest already pin down, so it
// takes no sequence number and stays out of the events digest: turning snapshots on or off, or changing
// their interval, leaves every event, fingerprint and checkpoint as it was.
#pragma once

#include <cstdint>
#include <vector>

#include "core/population/population.hpp"

namespace kessler {

// Classical osculating elements of a TEME state (m, m/s) about the Earth (kEarthMu_m3_s2). Angles in
// radians: inclination in [0, pi], RAAN, argument of perigee and mean anomaly in [0, 2 pi). Circular
// orbits: argument of perigee 0 (the anomaly counts from the node); equatorial ones: RAAN 0 (the node
// is the x axis). Unbound states (e >= 1) give a negative semi-major axis and a mean anomaly of 0.
struct OsculatingElements {
  double semi_major_axis_m = 0.0;
  double eccentricity = 0.0;
  double inclination_rad = 0.0;
  double raan_rad = 0.0;
  double argument_of_perigee_rad = 0.0;
  double mean_anomaly_rad = 0.0;
};
OsculatingElements osculating_elements(double x_m, double y_m, double z_m, double vx_m_s, double vy_m_s,
                                       double vz_m_s);

// Every object alive at one boundary, column by column in population order. Sizes and elements are
// 32-bit floats: 7 significant digits (a to under a metre, angles to 1e-7 rad) are far finer than any
// figure, and halve the size of a snapshot series.
struct PopulationSnapshot {
  std::int64_t step = 0;    // steps completed
  double sim_time_s = 0.0;  // since the scenario epoch
  std::vector<ObjectId> id;
  std::vector<ObjectType> type;
  std::vector<ObjectStatus> status;
  std::vector<float> radius_m, mass_kg;
  std::vector<float> semi_major_axis_m, eccentricity, inclination_rad, raan_rad, argument_of_perigee_rad,
      mean_anomaly_rad;

  std::size_t size() const { return id.size(); }
  void resize(std::size_t n);
};

// The snapshot of `population` after `step` steps (at sim_time_s).
PopulationSnapshot take_snapshot(const Population& population, std::int64_t step, double sim_time_s);

// What an object is in the figures and the API: the catalog's (or the launch plan's) type, or a
// fragment of one of the run's breakups (ids in [kFirstFragmentId, kFirstLaunchId)).
enum class ObjectKind : std::uint8_t { kPayload, kRocketBody, kDebris, kUnknown, kFragment };
ObjectKind kind_of(ObjectId id, ObjectType type);
const char* kind_name(ObjectKind kind);  // "payload", "rocket body", "debris", "unknown", "fragment"

// Spatial density against altitude (the figures' and `kessler show`'s): each bound orbit spread over
// shells of `shell_km` by the time it spends in each (64 equal steps of mean anomaly); an orbit reaching
// outside [first, last] counts in the outermost shell, so density times shell volume summed over the
// shells is the number of bound objects. Altitudes above the equatorial radius.
struct DensityProfile {
  double shell_km = 20.0;
  double first_altitude_km = 0.0;  // lower edge of the first shell
  std::vector<double> objects_per_km3;
  std::uint64_t objects = 0;  // bound objects spread over the shells
  std::uint64_t unbound = 0;  // e >= 1 or a <= 0: left out
  // Centre of the densest shell [km].
  double peak_altitude_km() const;
};
DensityProfile spatial_density(const PopulationSnapshot& snapshot, double first_altitude_km,
                               double last_altitude_km, double shell_km = 20.0);

// Snapshots every this many steps (and at the start and the last step): `every_s` simulated seconds
// rounded to whole steps (at least 1); every_s < 0 (unset): about 50 per run; 0: off (returns 0).
std::int64_t snapshot_interval_steps(double every_s, double dt_s, std::int64_t total_steps);

}  // namespace kessler
