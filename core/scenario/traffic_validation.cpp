// The scenario's `traffic` block: range and consistency checks with field paths, the shipped plans and
// the bundled catalog as sources of launches, and the mapping onto TrafficSettings.
#include "core/scenario/traffic_validation.hpp"

#include <cmath>
#include <fstream>
#include <sstream>
#include <utility>
#include <vector>

#include "core/catalog/bundled_datasets.hpp"
#include "core/catalog/tle.hpp"
#include "core/scenario/scenario_defaults.hpp"
#include "core/traffic/business_as_usual.hpp"

namespace kessler {
namespace {

namespace d = scenario_defaults;

std::string number(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

std::string shipped_names() {
  std::string names;
  for (std::string_view n : kShippedPlans) names += (names.empty() ? "" : ", ") + std::string(n);
  return names;
}

bool is_shipped(const std::string& name) {
  for (std::string_view n : kShippedPlans)
    if (name == n) return true;
  return false;
}

std::optional<FieldError> validate_plans(const v1::Traffic& t) {
  if (!t.launch_plan_csv().empty()) {
    LaunchPlan plan;
    try {
      plan = parse_launch_plan_csv(t.launch_plan_csv());
    } catch (const LaunchPlanError& e) {
      return FieldError{"traffic.launch_plan_csv", e.what()};
    }
    unsigned long long objects = 0;
    for (const LaunchRow& r : plan.rows) objects += r.count;
    if (objects > d::kTrafficMaxPlannedObjects)
      return FieldError{"traffic.launch_plan_csv", "launches " + std::to_string(objects) +
                                                       " objects, more than " +
                                                       std::to_string(d::kTrafficMaxPlannedObjects)};
  }
  for (int i = 0; i < t.plans_size(); ++i) {
    const std::string path = "traffic.plans[" + std::to_string(i) + "]";
    if (!is_shipped(t.plans(i)))
      return FieldError{path,
                        "no shipped plan '" + t.plans(i) + "' (expected one of: " + shipped_names() + ")"};
    for (int k = 0; k < i; ++k)
      if (t.plans(k) == t.plans(i))
        return FieldError{path, "is plans[" + std::to_string(k) + "] again ('" + t.plans(i) +
                                    "'); each plan launches its objects once"};
  }
  return std::nullopt;
}

std::optional<FieldError> validate_business_as_usual(const v1::BusinessAsUsual& b) {
  if (b.has_window_years()) {
    const double y = b.window_years();
    if (!std::isfinite(y))
      return FieldError{"traffic.business_as_usual.window_years",
                        "must be a finite number, got " + number(y)};
    if (!(y > 0.0))
      return FieldError{"traffic.business_as_usual.window_years", "must be positive, got " + number(y)};
  }
  if (!b.window_end().empty()) {
    std::string why;
    if (!UtcEpoch::parse_iso8601(b.window_end(), &why))
      return FieldError{"traffic.business_as_usual.window_end", why};
  }
  return std::nullopt;
}

std::optional<FieldError> validate_catalog_lifetime(const v1::Traffic& t) {
  if (t.has_catalog_active_lifetime_years() &&
      !(t.catalog_active_lifetime_years() >= 0.0 && t.catalog_active_lifetime_years() <= 100.0))
    return FieldError{"traffic.catalog_active_lifetime_years",
                      "must be in [0, 100] years, got " + number(t.catalog_active_lifetime_years())};
  return std::nullopt;
}

std::optional<FieldError> validate_disposal(const v1::Disposal& p) {
  if (p.has_success_probability() && !(p.success_probability() >= 0.0 && p.success_probability() <= 1.0))
    return FieldError{"traffic.disposal.success_probability",
                      "must be in [0, 1], got " + number(p.success_probability())};
  if (p.has_target_lifetime_years()) {
    const double y = p.target_lifetime_years();
    if (!std::isfinite(y))
      return FieldError{"traffic.disposal.target_lifetime_years",
                        "must be a finite number, got " + number(y)};
    if (!(y > 0.0))
      return FieldError{"traffic.disposal.target_lifetime_years", "must be positive, got " + number(y)};
  }
  return std::nullopt;
}

// A plan read from a file (a shipped plan): unreadable or refused, the error names `path`.
std::optional<FieldError> read_plan_file(const std::string& file, const std::string& path, LaunchPlan& out) {
  std::ifstream in(file, std::ios::binary);
  if (!in) return FieldError{path, "cannot read the shipped plan '" + file + "'"};
  std::ostringstream text;
  text << in.rdbuf();
  try {
    out = parse_launch_plan_csv(text.str());
  } catch (const LaunchPlanError& e) {
    return FieldError{path, file + ": " + e.what()};
  }
  return std::nullopt;
}

// Business as usual from the bundled SATCAT and catalog (core/catalog/bundled_datasets.hpp).
std::optional<FieldError> business_as_usual_of(const v1::BusinessAsUsual& b, const UtcEpoch& start,
                                               const UtcEpoch& until, const std::string& datasets_dir,
                                               LaunchPlan& out) {
  const std::string path = "traffic.business_as_usual";
  std::string why;
  const auto input = load_bundled_catalog("catalog-2022", datasets_dir, &why);
  if (!input) return FieldError{path, why};
  std::vector<MeanElements> sets;
  for (const ElementSetEntry& e : parse_tle_text(input->text, {}, input->source).sets)
    sets.push_back(e.elements);
  std::vector<LaunchRecord> records;
  try {
    records = launch_records(input->satcat_csv, sets);
  } catch (const LaunchPlanError& e) {
    return FieldError{path, input->satcat_source + ": " + e.what()};
  }
  const UtcEpoch window_end = b.window_end().empty() ? start : *UtcEpoch::parse_iso8601(b.window_end());
  const double years = b.has_window_years() ? b.window_years() : d::kTrafficWindowYears;
  out = business_as_usual_plan(records, window_end, years, until);
  return std::nullopt;
}

void append_rows(LaunchPlan& plan, LaunchPlan&& more) {
  for (LaunchRow& r : more.rows) plan.rows.push_back(std::move(r));
}

}  // namespace

std::string shipped_plan_path(std::string_view name, const std::string& traffic_dir) {
  return traffic_dir + "/" + std::string(name) + ".csv";
}

std::optional<FieldError> validate_traffic(const v1::Scenario& scenario) {
  const v1::Traffic& t = scenario.traffic();
  if (auto e = validate_plans(t)) return e;
  if (auto e = validate_business_as_usual(t.business_as_usual())) return e;
  if (auto e = validate_disposal(t.disposal())) return e;
  if (auto e = validate_catalog_lifetime(t)) return e;
  if (!(t.has_enabled() && t.enabled())) return std::nullopt;
  if (scenario.propagator() == v1::PROPAGATOR_SGP4)
    return FieldError{"traffic.enabled",
                      "traffic needs the numerical propagator (SGP4 cannot move launched objects, which have "
                      "no element sets); set propagator: numerical or leave it out"};
  const bool bau = t.business_as_usual().has_enabled() && t.business_as_usual().enabled();
  if (t.launch_plan_csv().empty() && t.plans_size() == 0 && !bau &&
      !(t.catalog_active_lifetime_years() > 0.0))
    return FieldError{"traffic.enabled",
                      "nothing to do: give launch_plan_csv, plans, business_as_usual (enabled: true) or "
                      "catalog_active_lifetime_years"};
  return std::nullopt;
}

TrafficSettings traffic_settings_of(const v1::Traffic& t) {
  TrafficSettings s;
  s.enabled = t.has_enabled() && t.enabled();
  const v1::Disposal& p = t.disposal();
  s.disposal.success_probability =
      p.has_success_probability() ? p.success_probability() : d::kDisposalSuccessProbability;
  s.disposal.target_lifetime_years =
      p.has_target_lifetime_years() ? p.target_lifetime_years() : d::kDisposalTargetLifetimeYears;
  s.disposal.deorbit = p.has_deorbit() && p.deorbit();
  s.catalog_active_lifetime_years = t.catalog_active_lifetime_years();
  return s;
}

std::optional<FieldError> traffic_plan_of(const v1::Traffic& t, const UtcEpoch& start, const UtcEpoch& until,
                                          const TrafficSources& sources, LaunchPlan& out) {
  out = LaunchPlan{};
  if (!t.launch_plan_csv().empty()) {
    try {
      out = parse_launch_plan_csv(t.launch_plan_csv());
    } catch (const LaunchPlanError& e) {
      return FieldError{"traffic.launch_plan_csv", e.what()};
    }
  }
  for (int i = 0; i < t.plans_size(); ++i) {
    LaunchPlan named;
    if (auto e = read_plan_file(shipped_plan_path(t.plans(i), sources.traffic_dir),
                                "traffic.plans[" + std::to_string(i) + "]", named))
      return e;
    append_rows(out, std::move(named));
  }
  if (t.business_as_usual().has_enabled() && t.business_as_usual().enabled()) {
    LaunchPlan bau;
    if (auto e = business_as_usual_of(t.business_as_usual(), start, until, sources.datasets_dir, bau))
      return e;
    append_rows(out, std::move(bau));
  }
  return std::nullopt;
}

std::optional<FieldError> traffic_launches_of(const v1::Scenario& scenario, const SimulationConfig& config,
                                              const TrafficSources& sources,
                                              std::vector<PlannedObject>& out) {
  out.clear();
  if (!config.traffic.enabled) return std::nullopt;
  LaunchPlan plan;
  const UtcEpoch until = config.start_epoch.plus_seconds(config.duration_s);
  if (auto e = traffic_plan_of(scenario.traffic(), config.start_epoch, until, sources, plan)) return e;
  out = expand_launch_plan(plan, config.start_epoch, config.duration_s, config.seed);
  return std::nullopt;
}

}  // namespace kessler
