// Range and consistency checks of a scenario, and its mapping onto the core's SimulationConfig.
#include <algorithm>
#include <cmath>
#include <sstream>

#include "core/catalog/leo19647.hpp"
#include "core/conjunctions/detector.hpp"
#include "core/scenario/breakup_validation.hpp"
#include "core/scenario/enum_names.hpp"
#include "core/scenario/input_file.hpp"
#include "core/scenario/run_builder.hpp"
#include "core/scenario/scenario_defaults.hpp"
#include "core/scenario/traffic_validation.hpp"

namespace kessler {
namespace {

namespace d = scenario_defaults;

std::string number(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

std::optional<FieldError> positive(bool has, double v, const char* path) {
  if (has && !(v > 0.0 && std::isfinite(v))) return FieldError{path, "must be positive, got " + number(v)};
  return std::nullopt;
}
std::optional<FieldError> non_negative(bool has, double v, const char* path) {
  if (has && !(v >= 0.0 && std::isfinite(v)))
    return FieldError{path, "must not be negative, got " + number(v)};
  return std::nullopt;
}

// Every enum field set anywhere in the message holds a number its type defines: a message sent over
// the wire may carry any number, which would otherwise silently mean the default.
std::optional<FieldError> validate_enums(const google::protobuf::Message& msg, const std::string& path) {
  namespace pb = google::protobuf;
  const pb::Reflection* refl = msg.GetReflection();
  std::vector<const pb::FieldDescriptor*> fields;
  refl->ListFields(msg, &fields);
  for (const pb::FieldDescriptor* f : fields) {
    const std::string here = path.empty() ? f->name() : path + "." + f->name();
    const int count = f->is_repeated() ? refl->FieldSize(msg, f) : 1;
    for (int i = 0; i < count; ++i) {
      const std::string at = f->is_repeated() ? here + "[" + std::to_string(i) + "]" : here;
      if (f->cpp_type() == pb::FieldDescriptor::CPPTYPE_ENUM) {
        const int number =
            f->is_repeated() ? refl->GetRepeatedEnumValue(msg, f, i) : refl->GetEnumValue(msg, f);
        if (!f->enum_type()->FindValueByNumber(number))
          return FieldError{at, "unknown value " + std::to_string(number) +
                                    " (expected one of: " + short_enum_choices(f->enum_type()) + ")"};
      } else if (f->cpp_type() == pb::FieldDescriptor::CPPTYPE_MESSAGE) {
        const pb::Message& sub =
            f->is_repeated() ? refl->GetRepeatedMessage(msg, f, i) : refl->GetMessage(msg, f);
        if (auto e = validate_enums(sub, at)) return e;
      }
    }
  }
  return std::nullopt;
}

// What the conjunction detector would refuse when the run starts (a screening distance whose cutoff
// exceeds the grid's domain, a step too long), checked at submission.
std::optional<FieldError> validate_detector(const v1::Scenario& s) {
  const SimulationConfig config = to_simulation_config(s);
  if (!config.conjunctions_enabled) return std::nullopt;
  auto problem = ConjunctionDetector::validate(config.conjunctions, config.dt_s);
  if (!problem) return std::nullopt;
  std::string path = "conjunctions";
  if (problem->rfind("kappa_max", 0) == 0) path = "conjunctions.kappa_max";
  if (problem->rfind("screening_distance_m", 0) == 0) path = "conjunctions.screening_distance_km";
  if (problem->rfind("dt_s", 0) == 0) path = "dt_s";
  return FieldError{path, *problem};
}

bool is_leo19647(const v1::Scenario& s) {
  return s.population().has_dataset() && s.population().dataset() == "leo-19647";
}

// A dataset of states (not element sets) fixes the epoch: leo-19647's states are at its own epoch.
UtcEpoch start_of(const v1::Scenario& s) {
  if (s.start_epoch().empty())
    return *UtcEpoch::parse_iso8601(is_leo19647(s) ? kLeo19647EpochIso : d::kStartEpoch);
  return *UtcEpoch::parse_iso8601(s.start_epoch());
}

double duration_s_of(const v1::Scenario& s) {
  if (s.has_end_epoch()) return UtcEpoch::parse_iso8601(s.end_epoch())->seconds_since(start_of(s));
  return (s.has_duration_days() ? s.duration_days() : d::kDurationDays) * 86400.0;
}

// The force model's enums (atmosphere, drag coupling) known, and the atmosphere's solar activity: constants
// in range, and only with NRLMSISE-00.
std::optional<FieldError> validate_solar_activity(const v1::ForceModel& f) {
  if (!v1::Atmosphere_IsValid(f.atmosphere()))
    return FieldError{"force_model.atmosphere", "unknown value " + std::to_string(f.atmosphere())};
  if (!v1::DragCoupling_IsValid(f.drag_coupling()))
    return FieldError{"force_model.drag_coupling", "unknown value " + std::to_string(f.drag_coupling())};
  if (!f.has_solar_activity()) return std::nullopt;
  const auto& sun = f.solar_activity();
  if (f.atmosphere() != v1::ATMOSPHERE_NRLMSISE00)
    return FieldError{"force_model.solar_activity", "only the nrlmsise00 atmosphere reads solar activity"};
  if (!v1::SolarActivityMode_IsValid(sun.mode()))
    return FieldError{"force_model.solar_activity.mode", "unknown value " + std::to_string(sun.mode())};
  const bool constant = sun.mode() == v1::SOLAR_ACTIVITY_MODE_CONSTANT;
  if ((sun.has_f107_sfu() || sun.has_ap()) && !constant)
    return FieldError{
        sun.has_f107_sfu() ? "force_model.solar_activity.f107_sfu" : "force_model.solar_activity.ap",
        "only the constant mode takes fixed values"};
  if (sun.has_f107_sfu() && !(sun.f107_sfu() > 0.0 && sun.f107_sfu() <= 1000.0))
    return FieldError{"force_model.solar_activity.f107_sfu",
                      "must be in (0, 1000] sfu, got " + number(sun.f107_sfu())};
  if (sun.has_ap() && !(sun.ap() >= 0.0 && sun.ap() <= 400.0))
    return FieldError{"force_model.solar_activity.ap", "must be in [0, 400], got " + number(sun.ap())};
  return std::nullopt;
}

std::optional<FieldError> validate_rules(const v1::IngestRules& r) {
  if (auto e = non_negative(r.has_min_perigee_km(), r.min_perigee_km(), "population.rules.min_perigee_km"))
    return e;
  if (auto e = positive(r.has_max_apogee_km(), r.max_apogee_km(), "population.rules.max_apogee_km")) return e;
  const double lo = r.has_min_perigee_km() ? r.min_perigee_km() : d::kMinPerigeeKm;
  const double hi = r.has_max_apogee_km() ? r.max_apogee_km() : d::kMaxApogeeKm;
  if (lo >= hi)
    return FieldError{"population.rules.max_apogee_km",
                      "must be above min_perigee_km (" + number(lo) + " km), got " + number(hi) + " km"};
  if (auto e = non_negative(r.has_max_epoch_after_start_days(), r.max_epoch_after_start_days(),
                            "population.rules.max_epoch_after_start_days"))
    return e;
  for (int i = 0; i < r.exclude_names_size(); ++i)
    if (r.exclude_names(i).empty())
      return FieldError{"population.rules.exclude_names[" + std::to_string(i) + "]", "must not be empty"};
  for (int i = 0; i < r.object_types_size(); ++i) {
    bool known = false;
    for (auto t : d::kObjectTypes) known |= r.object_types(i) == t;
    if (!known)
      return FieldError{"population.rules.object_types[" + std::to_string(i) + "]",
                        "unknown object type '" + r.object_types(i) +
                            "' (expected one of: PAYLOAD, ROCKET BODY, DEBRIS, UNKNOWN)"};
  }
  struct Size {
    bool has_mean, has_sd;
    double mean, sd;
    const char *mean_path, *sd_path;
  };
  for (const Size& s :
       {Size{r.has_small_radius_mean_m(), r.has_small_radius_stddev_m(), r.small_radius_mean_m(),
             r.small_radius_stddev_m(), "population.rules.small_radius_mean_m",
             "population.rules.small_radius_stddev_m"},
        Size{r.has_medium_radius_mean_m(), r.has_medium_radius_stddev_m(), r.medium_radius_mean_m(),
             r.medium_radius_stddev_m(), "population.rules.medium_radius_mean_m",
             "population.rules.medium_radius_stddev_m"},
        Size{r.has_large_radius_mean_m(), r.has_large_radius_stddev_m(), r.large_radius_mean_m(),
             r.large_radius_stddev_m(), "population.rules.large_radius_mean_m",
             "population.rules.large_radius_stddev_m"}}) {
    if (auto e = positive(s.has_mean, s.mean, s.mean_path)) return e;
    if (auto e = non_negative(s.has_sd, s.sd, s.sd_path)) return e;
  }
  return std::nullopt;
}

std::optional<FieldError> validate_population(const v1::Scenario& scenario) {
  const v1::PopulationSource& p = scenario.population();
  switch (p.source_case()) {
    case v1::PopulationSource::SOURCE_NOT_SET:
      return FieldError{"population",
                        "a population source is required (dataset, catalog, synthetic or state_table)"};
    case v1::PopulationSource::kDataset: {
      bool known = false;
      for (auto name : d::kDatasets) known |= p.dataset() == name;
      if (!known)
        return FieldError{"population.dataset", "unknown dataset '" + p.dataset() +
                                                    "' (available: catalog-2022, catalog-2019, leo-19647)"};
      break;
    }
    case v1::PopulationSource::kCatalog:
      if (p.catalog().text().find_first_not_of(" \t\r\n") == std::string::npos)
        return FieldError{"population.catalog.text", "is empty"};
      break;
    case v1::PopulationSource::kSynthetic: {
      const auto& s = p.synthetic();
      if (s.objects() == 0) return FieldError{"population.synthetic.objects", "must be at least 1"};
      if (s.objects() > 10'000'000)
        return FieldError{"population.synthetic.objects",
                          "must be at most 10000000, got " + std::to_string(s.objects())};
      if (s.has_active_fraction() && !(s.active_fraction() >= 0.0 && s.active_fraction() <= 1.0))
        return FieldError{"population.synthetic.active_fraction",
                          "must be in [0, 1], got " + number(s.active_fraction())};
      const double lo = s.has_min_altitude_km() ? s.min_altitude_km() : d::kSyntheticMinAltitudeKm;
      const double hi = s.has_max_altitude_km() ? s.max_altitude_km() : d::kSyntheticMaxAltitudeKm;
      // The generator's band: from 100 km (lower orbits decay within a day) to 40,000 km.
      if (!(lo >= 100.0 && lo < 40000.0))
        return FieldError{"population.synthetic.min_altitude_km",
                          "must be in [100, 40000) km, got " + number(lo)};
      if (!(hi <= 40000.0))
        return FieldError{"population.synthetic.max_altitude_km",
                          "must be at most 40000 km, got " + number(hi)};
      if (!(hi > lo))
        return FieldError{"population.synthetic.max_altitude_km",
                          "must be above min_altitude_km (" + number(lo) + " km), got " + number(hi) + " km"};
      break;
    }
    case v1::PopulationSource::kStateTable:
      if (p.state_table().find_first_not_of(" \t\r\n") == std::string::npos)
        return FieldError{"population.state_table", "is empty"};
      break;
  }
  if (p.has_max_objects() && p.max_objects() == 0)
    return FieldError{"population.max_objects", "must be at least 1 (leave it out for all objects)"};
  if (auto e = validate_rules(p.rules())) return e;
  const bool element_sets = p.has_catalog() || (p.has_dataset() && p.dataset() != "leo-19647");
  if (scenario.propagator() == v1::PROPAGATOR_SGP4 && !element_sets)
    return FieldError{"propagator", "sgp4 needs element sets: a catalog or a bundled catalog dataset"};
  if (p.ballistic_coefficients() == v1::BALLISTIC_COEFFICIENTS_FITTED && !element_sets)
    return FieldError{
        "population.ballistic_coefficients",
        "fitted needs element sets (their observed decay): a catalog or a bundled catalog dataset"};
  return std::nullopt;
}

}  // namespace

std::optional<FieldError> validate_scenario(const v1::Scenario& s) {
  if (auto e = validate_enums(s, "")) return e;
  std::string why;
  if (!s.start_epoch().empty() && !UtcEpoch::parse_iso8601(s.start_epoch(), &why))
    return FieldError{"start_epoch", why};
  if (is_leo19647(s) && !(start_of(s) == leo19647_epoch()))
    return FieldError{"start_epoch", std::string("must be the leo-19647 states' epoch, ") +
                                         kLeo19647EpochIso + " (or left out)"};
  if (s.has_end_epoch()) {
    if (!UtcEpoch::parse_iso8601(s.end_epoch(), &why)) return FieldError{"end_epoch", why};
    if (!(duration_s_of(s) > 0.0)) return FieldError{"end_epoch", "must be after start_epoch"};
  }
  if (auto e = positive(s.has_duration_days(), s.duration_days(), "duration_days")) return e;
  if (auto e = positive(s.has_dt_s(), s.dt_s(), "dt_s")) return e;
  const double dt = s.has_dt_s() ? s.dt_s() : d::kDtS;
  const double duration = duration_s_of(s);
  if (duration < dt)
    return FieldError{
        s.has_end_epoch() ? "end_epoch" : "duration_days",
        "the run (" + number(duration) + " s) is shorter than one step (dt_s = " + number(dt) + " s)"};
  if (duration / dt > 1e10) return FieldError{"dt_s", "gives more than 1e10 steps"};
  if (s.has_burn_up_altitude_km() && !(s.burn_up_altitude_km() >= 0.0 && s.burn_up_altitude_km() < 2000.0))
    return FieldError{"burn_up_altitude_km", "must be in [0, 2000), got " + number(s.burn_up_altitude_km())};
  if (s.has_progress_every_steps() && s.progress_every_steps() < 1)
    return FieldError{"progress_every_steps", "must be at least 1"};
  if (s.checkpoints().has_every_steps() && s.checkpoints().every_steps() < 0)
    return FieldError{"checkpoints.every_steps", "must not be negative (0 turns it off)"};
  if (auto e = non_negative(s.checkpoints().has_every_wall_s(), s.checkpoints().every_wall_s(),
                            "checkpoints.every_wall_s"))
    return e;
  if (auto e =
          non_negative(s.snapshots().has_every_days(), s.snapshots().every_days(), "snapshots.every_days"))
    return e;
  const auto& c = s.conjunctions();
  if (c.has_kappa_max() && !(c.kappa_max() > 0.0 && c.kappa_max() <= 10.0))
    return FieldError{"conjunctions.kappa_max", "must be in (0, 10], got " + number(c.kappa_max())};
  if (auto e = positive(c.has_screening_distance_km(), c.screening_distance_km(),
                        "conjunctions.screening_distance_km"))
    return e;
  if (auto e =
          non_negative(c.has_active_passive_max_passive_radius_m(), c.active_passive_max_passive_radius_m(),
                       "conjunctions.active_passive_max_passive_radius_m"))
    return e;
  if (c.has_active_passive_evasion_efficiency() &&
      !(c.active_passive_evasion_efficiency() >= 0.0 && c.active_passive_evasion_efficiency() <= 1.0))
    return FieldError{"conjunctions.active_passive_evasion_efficiency",
                      "must be in [0, 1], got " + number(c.active_passive_evasion_efficiency())};
  if (auto e = validate_solar_activity(s.force_model())) return e;
  // The breakups' epochs fall in the steps the run takes: floor(duration / dt) whole steps.
  SimulationConfig steps;
  steps.duration_s = duration;
  steps.dt_s = dt;
  if (auto e = validate_breakups(s, start_of(s), static_cast<double>(total_steps_of(steps)) * dt)) return e;
  if (auto e = validate_traffic(s)) return e;
  if (auto e = validate_population(s)) return e;
  return validate_detector(s);
}

SimulationConfig to_simulation_config(const v1::Scenario& s, int threads) {
  SimulationConfig c;
  c.start_epoch = start_of(s);
  c.duration_s = duration_s_of(s);
  c.dt_s = s.has_dt_s() ? s.dt_s() : d::kDtS;
  c.integrator = s.integrator() == v1::INTEGRATOR_YOSHIDA4 ? Integrator::kYoshida4 : Integrator::kBlanesMoan4;
  const auto& f = s.force_model();
  c.force_model.kepler = f.has_kepler() ? f.kepler() : true;
  c.force_model.j2 = f.has_j2() ? f.j2() : true;
  c.force_model.c22_s22 = f.has_c22_s22() ? f.c22_s22() : true;
  c.force_model.drag = f.has_drag() ? f.drag() : true;
  c.force_model.srp = f.has_srp() ? f.srp() : true;
  c.force_model.srp_earth_shadow = f.has_srp_earth_shadow() ? f.srp_earth_shadow() : true;
  c.force_model.atmosphere = f.atmosphere() == v1::ATMOSPHERE_EXPONENTIAL_FIT
                                 ? AtmosphereModel::kExponentialFit
                             : f.atmosphere() == v1::ATMOSPHERE_NRLMSISE00 ? AtmosphereModel::kNrlmsise00
                                                                           : AtmosphereModel::kDensityTable;
  c.force_model.drag_coupling =
      f.drag_coupling() == v1::DRAG_COUPLING_STEP_ENDS ? DragCoupling::kStepEnds : DragCoupling::kEveryKick;
  const auto& sun = f.solar_activity();
  c.force_model.solar_activity.mode = sun.mode() == v1::SOLAR_ACTIVITY_MODE_CYCLE ? SolarActivityMode::kCycle
                                      : sun.mode() == v1::SOLAR_ACTIVITY_MODE_CONSTANT
                                          ? SolarActivityMode::kConstant
                                          : SolarActivityMode::kObserved;
  c.force_model.solar_activity.f107_sfu = sun.has_f107_sfu() ? sun.f107_sfu() : d::kConstantF107Sfu;
  c.force_model.solar_activity.ap = sun.has_ap() ? sun.ap() : d::kConstantAp;
  const auto& k = s.conjunctions();
  c.conjunctions_enabled = k.has_enabled() ? k.enabled() : true;
  c.conjunctions.narrow_phase =
      k.narrow_phase() == v1::NARROW_PHASE_LINEAR ? NarrowPhase::kLinear : NarrowPhase::kHermite;
  c.conjunctions.kappa_max = k.has_kappa_max() ? k.kappa_max() : d::kKappaMax;
  c.conjunctions.screening_distance_m = k.has_screening_distance_km() ? k.screening_distance_km() * 1e3 : 0.0;
  c.conjunctions.active_pairs_evade = k.has_active_pairs_evade() ? k.active_pairs_evade() : true;
  c.conjunctions.active_passive_evasion_efficiency =
      k.has_active_passive_evasion_efficiency() ? k.active_passive_evasion_efficiency() : 1.0;
  c.conjunctions.active_passive_max_passive_radius_m = k.has_active_passive_max_passive_radius_m()
                                                           ? k.active_passive_max_passive_radius_m()
                                                           : d::kActivePassiveMaxPassiveRadiusM;
  c.burn_up_altitude_m = (s.has_burn_up_altitude_km() ? s.burn_up_altitude_km() : d::kBurnUpAltitudeKm) * 1e3;
  const std::int64_t total = total_steps_of(c);
  c.checkpoint_every_steps = s.checkpoints().has_every_steps()
                                 ? s.checkpoints().every_steps()
                                 : std::max<std::int64_t>(1, total / d::kCheckpointsPerRun);
  c.checkpoint_every_wall_s =
      s.checkpoints().has_every_wall_s() ? s.checkpoints().every_wall_s() : d::kCheckpointEveryWallS;
  c.progress_every_steps = s.has_progress_every_steps() ? s.progress_every_steps() : 0;
  c.snapshot_every_steps = snapshot_interval_steps(
      s.snapshots().has_every_days() ? s.snapshots().every_days() * 86400.0 : -1.0, c.dt_s, total);
  c.seed = s.has_seed() ? s.seed() : d::kSeed;
  c.threads = threads;
  c.breakups = breakup_settings_of(s.breakups(), c.start_epoch);
  c.traffic = traffic_settings_of(s.traffic());  // the launches: run_builder (traffic_launches_of)
  return c;
}

std::optional<FieldError> load_scenario_file(const std::string& path, v1::Scenario& out) {
  std::string why;
  auto text = read_input_file(path, &why);
  if (!text) return FieldError{"", "scenario file '" + path + "' " + why};
  return parse_scenario(*text, out);
}

}  // namespace kessler
