// The configuration key and the events and state digests (run_digests.hpp).
#include "core/simulation/run_digests.hpp"

#include <cstdint>
#include <string>

namespace kessler {
namespace {

// Event tags inside the events digest.
constexpr std::uint64_t kTagEncounter = 1, kTagBurnUp = 2, kTagProgress = 3, kTagBreakup = 4,
                        kTagLifecycle = 5;

void hash_breakup_settings(Sha256& h, const BreakupSettings& b) {
  h.update("breakups-v2");
  h.update_u64(static_cast<std::uint64_t>(b.on_collision));
  h.update_f64(b.separation_s);
  h.update_f64(b.min_characteristic_length_m);
  h.update_u64(b.mass_conservation);
  h.update_f64(b.explosion_scale);
  h.update_u64(b.max_fragments_per_event);
  h.update_u64(b.scheduled.size());
  for (const ScheduledBreakup& e : b.scheduled) {
    h.update_u64(e.step.has_value());
    h.update_u64(static_cast<std::uint64_t>(e.step.value_or(0)));
    h.update_f64(e.epoch_offset_s);
    h.update_u64(static_cast<std::uint64_t>(e.kind));
    h.update_u64(e.object_ids.size());
    for (ObjectId id : e.object_ids) h.update_u64(id);
    h.update_u64(e.impact_speed_m_s.has_value());
    h.update_f64(e.impact_speed_m_s.value_or(0.0));
    h.update_u64(e.masses_kg.size());
    for (double m : e.masses_kg) h.update_f64(m);
  }
}

void hash_traffic_settings(Sha256& h, const TrafficSettings& t) {
  h.update("traffic-v1");
  h.update_f64(t.disposal.success_probability);
  h.update_f64(t.disposal.target_lifetime_years);
  h.update_u64(t.disposal.deorbit);
  if (t.catalog_active_lifetime_years > 0.0) h.update_f64(t.catalog_active_lifetime_years);
  h.update_u64(t.launches.size());
  for (const PlannedObject& o : t.launches) {
    h.update_f64(o.epoch_offset_s);
    h.update_u64(o.row);
    h.update_u64(o.index);
    for (double v : {o.elements.semi_major_axis_m, o.elements.eccentricity, o.elements.inclination_rad,
                     o.elements.raan_rad, o.elements.argument_of_perigee_rad, o.elements.mean_anomaly_rad,
                     o.mass_kg, o.radius_m, o.lifetime_s})
      h.update_f64(v);
    h.update_u64(static_cast<std::uint64_t>(o.type));
    h.update_u64(o.manoeuvres);
  }
}

// An encounter's fields in for_each_field's order: integers and the kind as u64, doubles by their bits.
struct DigestField {
  Sha256& h;
  void operator()(const char*, std::uint64_t v) const { h.update_u64(v); }
  void operator()(const char*, double v) const { h.update_f64(v); }
  void operator()(const char*, EncounterKind kind) const { h.update_u64(static_cast<std::uint64_t>(kind)); }
  void operator()(const char*, const Eigen::Vector3d& v) const {
    for (int k = 0; k < 3; ++k) h.update_f64(v[k]);
  }
};

}  // namespace

// The configuration fields that shape results: a checkpoint from a run with other values is refused.
// Threads, checkpoint triggers and wall-time never change results, so they are left out.
std::string config_key(const SimulationConfig& c) {
  Sha256 h;
  h.update("kessler-config-v1");
  h.update_f64(c.start_epoch.jd_whole());
  h.update_f64(c.start_epoch.jd_fraction());
  h.update_f64(c.duration_s);
  h.update_f64(c.dt_s);
  const auto& f = c.force_model;
  for (bool b : {f.kepler, f.j2, f.c22_s22, f.drag, f.srp, f.srp_earth_shadow}) h.update_u64(b);
  h.update_u64(static_cast<std::uint64_t>(f.atmosphere));
  h.update_u64(c.conjunctions_enabled);
  const auto& k = c.conjunctions;
  h.update_u64(static_cast<std::uint64_t>(k.narrow_phase));
  h.update_f64(k.kappa_max);
  h.update_f64(k.screening_distance_m);
  h.update_u64(k.active_pairs_evade);
  h.update_f64(k.active_passive_max_passive_radius_m);
  // Only below 1, so that the keys of runs under the paper's rule stay as they were.
  if (k.active_passive_evasion_efficiency < 1.0) h.update_f64(k.active_passive_evasion_efficiency);
  h.update_f64(c.burn_up_altitude_m);
  h.update_u64(static_cast<std::uint64_t>(c.progress_every_steps));
  h.update_u64(c.seed);
  // Only when enabled, so that the keys (and checkpoints) of runs without breakups stay as they were.
  if (c.breakups.enabled) hash_breakup_settings(h, c.breakups);
  if (c.traffic.enabled) hash_traffic_settings(h, c.traffic);
  // Likewise the solar activity, only with the atmosphere that reads it.
  if (f.atmosphere == AtmosphereModel::kNrlmsise00) {
    h.update("nrlmsise00-grid-v1");
    h.update_u64(static_cast<std::uint64_t>(f.solar_activity.mode));
    h.update_f64(f.solar_activity.f107_sfu);
    h.update_f64(f.solar_activity.ap);
    if (f.solar_activity.mode != SolarActivityMode::kConstant)
      h.update((f.space_weather ? f.space_weather : SpaceWeather::bundled())->digest());
  }
  return h.hex_digest();
}

void hash_encounter(Sha256& h, std::uint64_t seq, const Encounter& e) {
  h.update_u64(kTagEncounter);
  h.update_u64(seq);
  for_each_field(e, DigestField{h});
}

void hash_burn_up(Sha256& h, std::uint64_t seq, const BurnUp& b) {
  h.update_u64(kTagBurnUp);
  h.update_u64(seq);
  h.update_u64(b.id);
  h.update_f64(b.time_s);
  h.update_f64(b.altitude_m);
}

void hash_breakup(Sha256& h, std::uint64_t seq, const BreakupReport& b) {
  h.update_u64(kTagBreakup);
  h.update_u64(seq);
  h.update_u64(b.breakup_id);
  h.update_u64(static_cast<std::uint64_t>(b.source));
  h.update_u64(b.event_index);
  h.update_f64(b.time_s);
  h.update_u64(static_cast<std::uint64_t>(b.kind));
  for (ObjectId id : b.parents) h.update_u64(id);
  h.update_u64(b.catastrophic);
  h.update_f64(b.specific_energy_j_per_g);
  h.update_u64(b.fragment_count);
  h.update_f64(b.fragment_mass_kg);
  h.update_u64(b.first_id);
  h.update_u64(b.last_id);
  h.update_u64(b.remnant_id);
  // The fragments' fields as one run of little-endian bytes (the digest is that of the same values
  // hashed one by one; one update per cloud instead of six per fragment).
  std::vector<std::uint8_t> bytes;
  bytes.reserve(b.fragments.size() * 48);
  auto put = [&bytes](std::uint64_t v) {
    for (int i = 0; i < 8; ++i) bytes.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
  };
  for (const FragmentReport& f : b.fragments) {
    put(f.id);
    put(f.parent_id);
    for (double v : {f.characteristic_length_m, f.area_to_mass_m2_kg, f.mass_kg, f.delta_v_m_s})
      put(std::bit_cast<std::uint64_t>(v));
  }
  h.update(bytes.data(), bytes.size());
}

void hash_lifecycle(Sha256& h, std::uint64_t seq, const LifecycleReport& e) {
  h.update_u64(kTagLifecycle);
  h.update_u64(seq);
  h.update_u64(static_cast<std::uint64_t>(e.kind));
  h.update_f64(e.time_s);
  h.update_u64(e.first_id);
  h.update_u64(e.last_id);
  h.update_u64(e.row);
  h.update_f64(e.altitude_m);
}

// Only the deterministic fields: wall time and ETA differ between runs.
void hash_progress(Sha256& h, std::uint64_t seq, const Progress& p) {
  h.update_u64(kTagProgress);
  h.update_u64(seq);
  h.update_u64(static_cast<std::uint64_t>(p.step));
  h.update_u64(static_cast<std::uint64_t>(p.total_steps));
  h.update_f64(p.sim_time_s);
  h.update_u64(p.objects_alive);
  h.update_u64(p.events_so_far);
}

std::string state_digest(const Population& p) {
  Sha256 h;
  h.update_u64(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) {
    h.update_u64(p.id[i]);
    for (const auto* v : {&p.state.x, &p.state.y, &p.state.z, &p.state.vx, &p.state.vy, &p.state.vz})
      h.update_f64((*v)[i]);
  }
  return h.hex_digest();
}

}  // namespace kessler
