// The scenario's `breakups` block: range and consistency checks with field paths, the checks against the
// ingested population, and the mapping onto BreakupSettings.
#include "core/scenario/breakup_validation.hpp"

#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "core/breakup/energy_and_count.hpp"
#include "core/scenario/scenario_defaults.hpp"

namespace kessler {
namespace {

namespace d = scenario_defaults;

std::string number(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

// Non-finite values cannot come from a scenario file (the parser refuses them) but can from the API.
std::optional<FieldError> positive_finite(double v, const std::string& path) {
  if (!std::isfinite(v)) return FieldError{path, "must be a finite number, got " + number(v)};
  if (!(v > 0.0)) return FieldError{path, "must be positive, got " + number(v)};
  return std::nullopt;
}

std::optional<FieldError> non_negative_finite(double v, const std::string& path) {
  if (!std::isfinite(v)) return FieldError{path, "must be a finite number, got " + number(v)};
  if (v < 0.0) return FieldError{path, "must not be negative, got " + number(v)};
  return std::nullopt;
}

std::optional<FieldError> validate_settings(const v1::Breakups& b, v1::Propagator propagator) {
  // Proto3 enums keep numbers the schema does not know (a newer client's); they are refused here.
  if (!v1::CollisionResponse_IsValid(b.on_collision()))
    return FieldError{"breakups.on_collision", "unknown value " + std::to_string(b.on_collision()) +
                                                   " (expected one of: fragment, record_only)"};
  if (b.has_separation_s())
    if (auto e = non_negative_finite(b.separation_s(), "breakups.separation_s")) return e;
  if (b.has_min_characteristic_length_m()) {
    const double lc = b.min_characteristic_length_m();
    if (!(lc > 0.0 && lc <= d::kBreakupMaxCharacteristicLengthM))
      return FieldError{"breakups.min_characteristic_length_m", "must be in (0, 1] m, got " + number(lc)};
  }
  if (b.has_explosion_scale_s())
    if (auto e = positive_finite(b.explosion_scale_s(), "breakups.explosion_scale_s")) return e;
  if (b.has_max_fragments_per_event() && b.max_fragments_per_event() == 0)
    return FieldError{"breakups.max_fragments_per_event", "must be at least 1"};
  if (b.enabled() && propagator == v1::PROPAGATOR_SGP4)
    return FieldError{"breakups.enabled",
                      "breakups need the numerical propagator (SGP4 cannot move fragments, which have no "
                      "element sets); set propagator: numerical or leave it out"};
  return std::nullopt;
}

std::optional<FieldError> validate_epoch(const v1::ScheduledBreakup& s, const std::string& path,
                                         const UtcEpoch& start, double run_s) {
  if (s.epoch().empty()) return FieldError{path, "is required (ISO 8601 UTC, e.g. 2009-02-10T16:56:00Z)"};
  std::string why;
  const auto epoch = UtcEpoch::parse_iso8601(s.epoch(), &why);
  if (!epoch) return FieldError{path, why};
  const double offset = epoch->seconds_since(start);
  if (!(offset >= 0.0 && offset < run_s))
    return FieldError{path, "must be within the run, [" + start.to_iso8601(0) + ", " +
                                start.plus_seconds(run_s).to_iso8601(0) + "), got " + s.epoch()};
  return std::nullopt;
}

std::optional<FieldError> validate_objects(const v1::ScheduledBreakup& s, const std::string& path) {
  const bool explosion = s.kind() == v1::BREAKUP_KIND_EXPLOSION;
  const int wanted = explosion ? 1 : 2;
  if (s.objects_size() != wanted)
    return FieldError{path + ".objects", std::string(explosion ? "an explosion takes exactly 1 object"
                                                               : "a collision takes exactly 2 objects") +
                                             ", got " + std::to_string(s.objects_size())};
  if (!explosion && s.objects(0) == s.objects(1))
    return FieldError{path + ".objects[1]", "is objects[0] again (" + std::to_string(s.objects(0)) +
                                                "); a collision takes two distinct objects"};
  if (s.has_impact_speed_m_s()) {
    if (explosion) return FieldError{path + ".impact_speed_m_s", "only a collision takes an impact speed"};
    if (auto e = non_negative_finite(s.impact_speed_m_s(), path + ".impact_speed_m_s")) return e;
  }
  if (s.masses_kg_size() != 0 && s.masses_kg_size() != s.objects_size())
    return FieldError{path + ".masses_kg", "give one mass per object (" + std::to_string(s.objects_size()) +
                                               ") or none, got " + std::to_string(s.masses_kg_size())};
  for (int k = 0; k < s.masses_kg_size(); ++k)
    if (auto e = positive_finite(s.masses_kg(k), path + ".masses_kg[" + std::to_string(k) + "]")) return e;
  return std::nullopt;
}

std::optional<FieldError> validate_scheduled(const v1::ScheduledBreakup& s, const std::string& path,
                                             const UtcEpoch& start, double run_s) {
  if (auto e = validate_epoch(s, path + ".epoch", start, run_s)) return e;
  if (s.kind() == v1::BREAKUP_KIND_UNSPECIFIED)
    return FieldError{path + ".kind", "is required (explosion or collision)"};
  if (!v1::BreakupKind_IsValid(s.kind()))
    return FieldError{path + ".kind", "unknown value " + std::to_string(s.kind()) +
                                          " (expected one of: explosion, collision)"};
  return validate_objects(s, path);
}

// The fragment count of scheduled event `index` as the model's plan_breakup counts it, checked against
// max_fragments_per_event before the run rather than when the event comes. Explosions need nothing but
// the settings. Collisions need their masses (masses_kg, else the population's when given) and
// impact_speed_m_s: without it the speed is the parents' relative speed at the breakup, known only
// then, and the core's own check refuses the event at run time.
std::optional<FieldError> check_fragment_count(const BreakupSettings& settings, std::size_t index,
                                               const Population* population) {
  const ScheduledBreakup& b = settings.scheduled[index];
  const double lc = settings.min_characteristic_length_m;
  double n = 0.0;
  if (b.kind == BreakupKind::kExplosion) {
    n = explosion_cumulative_count(settings.explosion_scale, lc);
  } else {
    if (!b.impact_speed_m_s) return std::nullopt;
    std::vector<double> m = b.masses_kg;
    if (m.empty()) {
      if (!population) return std::nullopt;
      for (ObjectId id : b.object_ids) {
        const auto i = population->index_of(id);
        if (!i) return std::nullopt;  // reported as an unknown object
        m.push_back(population->mass_kg[*i]);
      }
    }
    // The heavier parent is the target (on equal masses the first), as in plan_breakup.
    const double mt = m[0] > m[1] ? m[0] : m[1], mp = m[0] > m[1] ? m[1] : m[0];
    const double v = *b.impact_speed_m_s;
    const bool catastrophic = specific_energy_j_per_g(mt, mp, v) >= kCatastrophicThresholdJPerG;
    n = collision_cumulative_count(collision_mass_kg(catastrophic, mt, mp, v), lc);
  }
  if (std::floor(n) <= static_cast<double>(settings.max_fragments_per_event)) return std::nullopt;
  return FieldError{"breakups.scheduled[" + std::to_string(index) + "]",
                    "gives " + number(std::floor(n)) + " fragments of at least " + number(lc) +
                        " m, more than max_fragments_per_event (" +
                        std::to_string(settings.max_fragments_per_event) + ")"};
}

}  // namespace

std::optional<FieldError> validate_breakups(const v1::Scenario& scenario, const UtcEpoch& start,
                                            double run_s) {
  const v1::Breakups& b = scenario.breakups();
  if (auto e = validate_settings(b, scenario.propagator())) return e;
  for (int i = 0; i < b.scheduled_size(); ++i)
    if (auto e =
            validate_scheduled(b.scheduled(i), "breakups.scheduled[" + std::to_string(i) + "]", start, run_s))
      return e;
  const BreakupSettings settings = breakup_settings_of(b, start);
  for (std::size_t i = 0; i < settings.scheduled.size(); ++i)
    if (auto e = check_fragment_count(settings, i, nullptr)) return e;
  return std::nullopt;
}

std::optional<FieldError> check_breakups_against_population(const BreakupSettings& settings,
                                                            const Population& population) {
  if (!settings.enabled) return std::nullopt;
  for (std::size_t i = 0; i < settings.scheduled.size(); ++i) {
    const auto& ids = settings.scheduled[i].object_ids;
    for (std::size_t k = 0; k < ids.size(); ++k)
      if (!population.index_of(ids[k]))
        return FieldError{"breakups.scheduled[" + std::to_string(i) + "].objects[" + std::to_string(k) + "]",
                          "no object " + std::to_string(ids[k]) + " in the population"};
    if (auto e = check_fragment_count(settings, i, &population)) return e;
  }
  return std::nullopt;
}

BreakupSettings breakup_settings_of(const v1::Breakups& b, const UtcEpoch& start) {
  BreakupSettings s;
  s.enabled = b.has_enabled() && b.enabled();
  s.on_collision = b.on_collision() == v1::COLLISION_RESPONSE_RECORD_ONLY ? CollisionResponse::kRecordOnly
                                                                          : CollisionResponse::kFragment;
  s.separation_s = b.has_separation_s() ? b.separation_s() : d::kBreakupSeparationS;
  s.min_characteristic_length_m = b.has_min_characteristic_length_m() ? b.min_characteristic_length_m()
                                                                      : d::kBreakupMinCharacteristicLengthM;
  s.mass_conservation = b.has_mass_conservation() ? b.mass_conservation() : true;
  s.explosion_scale = b.has_explosion_scale_s() ? b.explosion_scale_s() : d::kBreakupExplosionScale;
  s.max_fragments_per_event =
      b.has_max_fragments_per_event() ? b.max_fragments_per_event() : d::kBreakupMaxFragmentsPerEvent;
  for (const v1::ScheduledBreakup& e : b.scheduled()) {
    ScheduledBreakup out;
    const auto epoch = UtcEpoch::parse_iso8601(e.epoch());
    out.epoch_offset_s = epoch ? epoch->seconds_since(start) : 0.0;
    out.kind = e.kind() == v1::BREAKUP_KIND_COLLISION ? BreakupKind::kCollision : BreakupKind::kExplosion;
    out.object_ids.assign(e.objects().begin(), e.objects().end());
    if (e.has_impact_speed_m_s()) out.impact_speed_m_s = e.impact_speed_m_s();
    out.masses_kg.assign(e.masses_kg().begin(), e.masses_kg().end());
    s.scheduled.push_back(std::move(out));
  }
  return s;
}

}  // namespace kessler
