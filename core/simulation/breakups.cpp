#include "core/simulation/breakups.hpp"

#include <algorithm>
#include <cmath>

#include "core/breakup/fragment_cloud.hpp"
#include "core/physics/constants.hpp"

namespace kessler {

std::int64_t breakup_boundary_step(const ScheduledBreakup& b, double dt_s) {
  if (b.step) return std::max<std::int64_t>(1, *b.step);
  // The tiny tolerance keeps an offset of k * dt_s on boundary k after rounding.
  const double steps = std::ceil(b.epoch_offset_s / dt_s * (1.0 - 1e-12));
  return std::max<std::int64_t>(1, static_cast<std::int64_t>(steps));
}

std::vector<std::size_t> breakups_due(const BreakupSettings& settings, std::int64_t step, double dt_s) {
  std::vector<std::size_t> out;
  if (!settings.enabled) return out;
  for (std::size_t i = 0; i < settings.scheduled.size(); ++i)
    if (breakup_boundary_step(settings.scheduled[i], dt_s) == step) out.push_back(i);
  return out;
}

std::optional<std::int64_t> next_breakup_step(const BreakupSettings& settings, std::int64_t step,
                                              double dt_s) {
  std::optional<std::int64_t> next;
  if (!settings.enabled) return next;
  for (const ScheduledBreakup& b : settings.scheduled) {
    const std::int64_t k = breakup_boundary_step(b, dt_s);
    if (k > step && (!next || k < *next)) next = k;
  }
  return next;
}

namespace {

// The model's class of a parent: rocket bodies (and, for explosions, objects of unknown type: most
// recorded explosions are upper stages) take the rocket-body A/m distributions, the rest the spacecraft's.
BreakupObjectClass object_class(BreakupKind kind, ObjectType type) {
  if (type == ObjectType::kRocketBody) return BreakupObjectClass::kRocketBody;
  if (kind == BreakupKind::kExplosion && type == ObjectType::kUnknown) return BreakupObjectClass::kRocketBody;
  return BreakupObjectClass::kSpacecraft;
}

// The model's event keyed by (seed, breakup number). Characteristic length: the collision diameter 2 r
// (a fragment's radius is Lc / 2, so the two stay one size measure).
BreakupEvent model_event(const BreakupSettings& settings, BreakupKind kind, BreakupId breakup_id,
                         std::uint64_t seed) {
  BreakupEvent e;
  e.kind = kind;
  e.explosion_scale = settings.explosion_scale;
  e.min_characteristic_length_m = settings.min_characteristic_length_m;
  e.conserve_mass = settings.mass_conservation;
  e.max_fragments_per_event = settings.max_fragments_per_event;
  e.event_id = breakup_id;
  e.seed = seed;
  return e;
}

BreakupParent model_parent(const Population& population, std::size_t i, BreakupKind kind, double mass_kg,
                           const Eigen::Vector3d& r_m, const Eigen::Vector3d& v_m_s) {
  BreakupParent p;
  p.id = population.id[i];
  p.mass_kg = mass_kg;
  p.characteristic_length_m = 2.0 * population.radius_m[i];
  p.object_class = object_class(kind, population.type[i]);
  p.position_m = {r_m.x(), r_m.y(), r_m.z()};
  p.velocity_m_s = {v_m_s.x(), v_m_s.y(), v_m_s.z()};
  return p;
}

// The cloud's fragments as passive debris, appended column by column (no per-object strings: a
// fragment's name is empty, hosts show "FRAGMENT <id>"): drag Cd A / m with Cd = 2.2, SRP A / m.
// `group`: their separation group (0 when the rule is off).
void append_fragments(const FragmentCloud& c, BreakupId group, ObjectId first_id, Population& p) {
  const std::size_t base = p.size(), n = c.size();
  p.append_default(n);
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t i = base + k;
    p.id[i] = first_id + k;
    p.state.x[i] = c.position_m.x[k];
    p.state.y[i] = c.position_m.y[k];
    p.state.z[i] = c.position_m.z[k];
    p.state.vx[i] = c.velocity_m_s.x[k];
    p.state.vy[i] = c.velocity_m_s.y[k];
    p.state.vz[i] = c.velocity_m_s.z[k];
    p.radius_m[i] = c.radius_m[k];
    p.mass_kg[i] = c.mass_kg[k];
    p.drag_area_to_mass_m2_kg[i] = constants::kDefaultDragCoefficient * c.area_to_mass_m2_kg[k];
    p.srp_area_to_mass_m2_kg[i] = c.area_to_mass_m2_kg[k];
    p.type[i] = ObjectType::kDebris;
    p.separation_group[i] = group;
  }
}

BreakupReport report_of(const FragmentCloud& cloud, const BreakupEvent& event, BreakupId breakup_id,
                        double time_s, ObjectId first_id) {
  BreakupReport r;
  r.breakup_id = breakup_id;
  r.time_s = time_s;
  r.kind = event.kind;
  for (const BreakupParent& p : event.parents) r.parents.push_back(p.id);
  r.catastrophic = cloud.catastrophic;
  r.specific_energy_j_per_g = cloud.specific_energy_j_per_g;
  r.fragment_count = cloud.size();
  r.fragment_mass_kg = cloud.fragment_mass_kg;
  if (cloud.size() > 0) {
    r.first_id = first_id;
    r.last_id = first_id + cloud.size() - 1;
  }
  if (cloud.remnant) r.remnant_id = cloud.remnant->parent_id;
  r.fragments.resize(cloud.size());
  for (std::size_t k = 0; k < cloud.size(); ++k) {
    FragmentReport& f = r.fragments[k];
    f.id = first_id + k;
    f.parent_id = event.parents[cloud.parent_index[k]].id;
    f.characteristic_length_m = cloud.characteristic_length_m[k];
    f.area_to_mass_m2_kg = cloud.area_to_mass_m2_kg[k];
    f.mass_kg = cloud.mass_kg[k];
    f.delta_v_m_s = std::sqrt(cloud.delta_v_m_s.x[k] * cloud.delta_v_m_s.x[k] +
                              cloud.delta_v_m_s.y[k] * cloud.delta_v_m_s.y[k] +
                              cloud.delta_v_m_s.z[k] * cloud.delta_v_m_s.z[k]);
  }
  return r;
}

// Parents out (the remnant's parent stays: its index is returned), fragments in with the next ids.
// A breakup at time_s separates its objects until time_s + separation_s.
std::optional<std::size_t> replace_parents(const BreakupSettings& settings, double time_s,
                                           const FragmentCloud& cloud, const std::vector<std::size_t>& at,
                                           BreakupId breakup_id, Population& population, BreakupIds& ids) {
  const bool separates = cloud.size() > 0 && settings.separation_s > 0.0;
  std::optional<std::size_t> remnant_at;
  std::vector<char> flags(population.size(), 0);
  for (std::size_t k = 0; k < at.size(); ++k) {
    if (cloud.remnant && cloud.remnant->parent_index == k) {
      const BreakupRemnant& m = *cloud.remnant;
      const std::size_t i = at[k];
      population.mass_kg[i] = m.mass_kg;
      population.state.vx[i] = m.velocity_m_s[0];
      population.state.vy[i] = m.velocity_m_s[1];
      population.state.vz[i] = m.velocity_m_s[2];
      // Separated from its fragments as they are from each other (the separation rule).
      population.separation_group[i] = separates ? breakup_id : 0;
      remnant_at = i;
      continue;
    }
    flags[at[k]] = 1;
  }
  if (remnant_at) {
    // Indices after a removed parent move down.
    std::size_t shift = 0;
    for (std::size_t i : at) shift += flags[i] && i < *remnant_at ? 1 : 0;
    *remnant_at -= shift;
  }
  population.remove_flagged(flags);
  append_fragments(cloud, separates ? breakup_id : 0, ids.next_fragment_id, population);
  if (separates) ids.separating.push_back({breakup_id, time_s + settings.separation_s});
  ids.next_fragment_id += cloud.size();
  return remnant_at;
}

}  // namespace

bool end_separations(double t_start_s, Population& population, BreakupIds& ids) {
  std::vector<BreakupId> over;
  std::erase_if(ids.separating, [&](const SeparatingBreakup& b) {
    if (b.until_s > t_start_s) return false;
    over.push_back(b.group);
    return true;
  });
  if (over.empty()) return false;
  for (BreakupId& g : population.separation_group)
    if (g != 0 && std::find(over.begin(), over.end(), g) != over.end()) g = 0;
  return true;
}

std::optional<std::int64_t> next_separation_end_step(const BreakupIds& ids, std::int64_t step, double dt_s) {
  std::optional<std::int64_t> next;
  for (const SeparatingBreakup& b : ids.separating) {
    // The first boundary k with k dt >= until_s, the same rounding as the scheduled breakups.
    const auto k = std::max<std::int64_t>(
        step + 1, static_cast<std::int64_t>(std::ceil(b.until_s / dt_s * (1.0 - 1e-12))));
    if (!next || k < *next) next = k;
  }
  return next;
}

std::optional<BreakupReport> apply_scheduled_breakup(const BreakupSettings& settings, std::size_t index,
                                                     std::uint64_t seed, double time_s,
                                                     Population& population, BreakupIds& ids) {
  const ScheduledBreakup& b = settings.scheduled[index];
  std::vector<std::size_t> at;
  for (ObjectId id : b.object_ids) {
    const std::optional<std::size_t> i = population.index_of(id);
    if (!i) return std::nullopt;
    at.push_back(*i);
  }
  const BreakupId breakup_id = ids.next_breakup_id;
  BreakupEvent event = model_event(settings, b.kind, breakup_id, seed);
  event.impact_speed_m_s = b.impact_speed_m_s;
  for (std::size_t k = 0; k < at.size(); ++k) {
    const std::size_t i = at[k];
    const double mass = k < b.masses_kg.size() ? b.masses_kg[k] : population.mass_kg[i];
    event.parents.push_back(model_parent(population, i, b.kind, mass, population.state.position(i),
                                         population.state.velocity(i)));
  }
  const FragmentCloud cloud = generate_fragments(event);
  ++ids.next_breakup_id;
  BreakupReport r = report_of(cloud, event, breakup_id, time_s, ids.next_fragment_id);
  r.source = BreakupSource::kScheduled;
  r.event_index = index;
  replace_parents(settings, time_s, cloud, at, breakup_id, population, ids);
  return r;
}

std::optional<BreakupReport> apply_collision_breakup(const BreakupSettings& settings,
                                                     const Encounter& collision, std::uint64_t seed,
                                                     double step_end_s, Population& population,
                                                     BreakupIds& ids, const PropagateObjects& propagate) {
  const std::optional<std::size_t> i1 = population.index_of(collision.id1);
  const std::optional<std::size_t> i2 = population.index_of(collision.id2);
  if (!i1 || !i2) return std::nullopt;
  const BreakupId breakup_id = ids.next_breakup_id;
  BreakupEvent event = model_event(settings, BreakupKind::kCollision, breakup_id, seed);
  event.parents.push_back(model_parent(population, *i1, BreakupKind::kCollision, population.mass_kg[*i1],
                                       collision.r1_m, collision.v1_m_s));
  event.parents.push_back(model_parent(population, *i2, BreakupKind::kCollision, population.mass_kg[*i2],
                                       collision.r2_m, collision.v2_m_s));
  FragmentCloud cloud = generate_fragments(event);
  ++ids.next_breakup_id;
  BreakupReport r = report_of(cloud, event, breakup_id, collision.tca_s, ids.next_fragment_id);
  r.source = BreakupSource::kCollision;
  // The fragments (and the remnant, from its parent's position at TCA) travel from TCA to the step's end.
  Population moving;
  const std::size_t n = cloud.size();
  append_fragments(cloud, 0, ids.next_fragment_id, moving);
  if (cloud.remnant) {
    const BreakupParent& parent = event.parents[cloud.remnant->parent_index];
    ObjectRecord rec = population.record(cloud.remnant->parent_index == 0 ? *i1 : *i2);
    rec.position_m = {parent.position_m[0], parent.position_m[1], parent.position_m[2]};
    rec.velocity_m_s = {cloud.remnant->velocity_m_s[0], cloud.remnant->velocity_m_s[1],
                        cloud.remnant->velocity_m_s[2]};
    moving.add(rec);
  }
  if (step_end_s > collision.tca_s && moving.size() > 0) propagate(moving, collision.tca_s, step_end_s);
  for (std::size_t k = 0; k < n; ++k) {
    cloud.position_m.x[k] = moving.state.x[k];
    cloud.position_m.y[k] = moving.state.y[k];
    cloud.position_m.z[k] = moving.state.z[k];
    cloud.velocity_m_s.x[k] = moving.state.vx[k];
    cloud.velocity_m_s.y[k] = moving.state.vy[k];
    cloud.velocity_m_s.z[k] = moving.state.vz[k];
  }
  if (cloud.remnant)
    cloud.remnant->velocity_m_s = {moving.state.vx[n], moving.state.vy[n], moving.state.vz[n]};
  const std::optional<std::size_t> remnant_at =
      replace_parents(settings, collision.tca_s, cloud, {*i1, *i2}, breakup_id, population, ids);
  if (remnant_at) population.state.set(*remnant_at, moving.state.position(n), moving.state.velocity(n));
  return r;
}

}  // namespace kessler
