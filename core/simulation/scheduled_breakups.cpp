#include "core/simulation/scheduled_breakups.hpp"

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

// The model's event from the parents' current states. Characteristic length: the collision diameter
// 2 r (a fragment's radius is Lc / 2, so the two stay one size measure). Area-to-mass class: explosions
// are those of rocket bodies (most recorded explosions are upper stages), collisions of spacecraft.
BreakupEvent model_event(const BreakupSettings& settings, std::size_t index, std::uint64_t seed,
                         const Population& population, const std::vector<std::size_t>& at) {
  const ScheduledBreakup& b = settings.scheduled[index];
  BreakupEvent e;
  e.kind = b.kind;
  e.impact_speed_m_s = b.impact_speed_m_s;
  e.explosion_scale = settings.explosion_scale;
  e.min_characteristic_length_m = settings.min_characteristic_length_m;
  e.conserve_mass = settings.mass_conservation;
  e.max_fragments_per_event = settings.max_fragments_per_event;
  e.event_id = index;
  e.seed = seed;
  for (std::size_t k = 0; k < at.size(); ++k) {
    const std::size_t i = at[k];
    BreakupParent p;
    p.id = population.id[i];
    p.mass_kg = k < b.masses_kg.size() ? b.masses_kg[k] : population.mass_kg[i];
    p.characteristic_length_m = 2.0 * population.radius_m[i];
    p.object_class =
        b.kind == BreakupKind::kExplosion ? BreakupObjectClass::kRocketBody : BreakupObjectClass::kSpacecraft;
    p.position_m = {population.state.x[i], population.state.y[i], population.state.z[i]};
    p.velocity_m_s = {population.state.vx[i], population.state.vy[i], population.state.vz[i]};
    e.parents.push_back(p);
  }
  return e;
}

// Fragment i of the cloud as a passive object: drag area-to-mass Cd A / m with Cd = 2.2, SRP A / m.
ObjectRecord fragment_record(const FragmentCloud& c, std::size_t i, ObjectId id) {
  ObjectRecord o;
  o.id = id;
  o.name = "FRAGMENT " + std::to_string(id);
  o.position_m = {c.position_m.x[i], c.position_m.y[i], c.position_m.z[i]};
  o.velocity_m_s = {c.velocity_m_s.x[i], c.velocity_m_s.y[i], c.velocity_m_s.z[i]};
  o.radius_m = c.radius_m[i];
  o.mass_kg = c.mass_kg[i];
  o.drag_area_to_mass_m2_kg = constants::kDefaultDragCoefficient * c.area_to_mass_m2_kg[i];
  o.srp_area_to_mass_m2_kg = c.area_to_mass_m2_kg[i];
  o.status = ObjectStatus::kPassive;
  return o;
}

}  // namespace

std::optional<BreakupReport> apply_scheduled_breakup(const BreakupSettings& settings, std::size_t index,
                                                     std::uint64_t seed, double time_s,
                                                     Population& population, ObjectId& next_id) {
  const ScheduledBreakup& b = settings.scheduled[index];
  std::vector<std::size_t> at;
  for (ObjectId id : b.object_ids) {
    const std::optional<std::size_t> i = population.index_of(id);
    if (!i) return std::nullopt;
    at.push_back(*i);
  }
  const FragmentCloud cloud = generate_fragments(model_event(settings, index, seed, population, at));
  BreakupReport r;
  r.event_index = index;
  r.time_s = time_s;
  r.kind = b.kind;
  r.parents = b.object_ids;
  r.catastrophic = cloud.catastrophic;
  r.specific_energy_j_per_g = cloud.specific_energy_j_per_g;
  r.fragment_count = cloud.size();
  r.fragment_mass_kg = cloud.fragment_mass_kg;
  // The remnant keeps its parent's entry (and id); every other parent leaves.
  std::vector<char> flags(population.size(), 0);
  for (std::size_t k = 0; k < at.size(); ++k) {
    if (cloud.remnant && cloud.remnant->parent_index == k) {
      const BreakupRemnant& m = *cloud.remnant;
      const std::size_t i = at[k];
      population.mass_kg[i] = m.mass_kg;
      population.state.vx[i] = m.velocity_m_s[0];
      population.state.vy[i] = m.velocity_m_s[1];
      population.state.vz[i] = m.velocity_m_s[2];
      continue;
    }
    flags[at[k]] = 1;
  }
  population.remove_flagged(flags);
  population.reserve(population.size() + cloud.size());
  for (std::size_t i = 0; i < cloud.size(); ++i) population.add(fragment_record(cloud, i, next_id++));
  if (cloud.size() > 0) {
    r.first_id = next_id - cloud.size();
    r.last_id = next_id - 1;
  }
  return r;
}

}  // namespace kessler
