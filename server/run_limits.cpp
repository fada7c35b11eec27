#include "server/run_limits.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <sstream>

#include "core/catalog/leo19647.hpp"

namespace kessler::server {
namespace {

// The bundled catalogs' 3LE files hold 23,939 (2022) and 17,892 (2019) objects
// (core/catalog/bundled_datasets.hpp); the filters keep fewer, so these bound the run.
constexpr std::uint64_t kCatalog2022Objects = 23939;
constexpr std::uint64_t kCatalog2019Objects = 17892;

std::string number(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

}  // namespace

RunEstimate estimate_run(const v1::Scenario& scenario, std::optional<std::uint64_t> ingested_objects) {
  const v1::PopulationSource& p = scenario.population();
  RunEstimate out;
  if (ingested_objects) {
    out.objects = *ingested_objects;
  } else if (p.has_synthetic()) {
    out.objects = p.synthetic().objects();
  } else if (p.has_dataset()) {
    out.objects = p.dataset() == "leo-19647"      ? kLeo19647Objects
                  : p.dataset() == "catalog-2019" ? kCatalog2019Objects
                                                  : kCatalog2022Objects;
  }
  if (p.has_max_objects()) out.objects = std::min<std::uint64_t>(out.objects, p.max_objects());
  out.steps = total_steps_of(to_simulation_config(scenario));
  out.object_steps = static_cast<double>(out.objects) * static_cast<double>(out.steps);
  out.wall_hours = out.object_steps * kEstimatedSecondsPerObjectStep / 3600.0;
  return out;
}

std::optional<FieldError> check_run_limits(const v1::Scenario& scenario, const RunEstimate& estimate,
                                           const RunLimits& limits) {
  const char* const duration_path = scenario.has_end_epoch() ? "end_epoch" : "duration_days";
  if (estimate.objects > limits.max_objects)
    return FieldError{"population", "the run would simulate " + std::to_string(estimate.objects) +
                                        " objects, above this daemon's limit of " +
                                        std::to_string(limits.max_objects) + " (--max-run-objects)"};
  if (estimate.steps > 0 && static_cast<std::uint64_t>(estimate.steps) > limits.max_steps)
    return FieldError{duration_path, "the run would take " + std::to_string(estimate.steps) +
                                         " steps, above this daemon's limit of " +
                                         std::to_string(limits.max_steps) + " (--max-run-steps)"};
  if (estimate.object_steps > limits.max_object_steps)
    return FieldError{duration_path, "the run would cost " + number(estimate.object_steps) +
                                         " object-steps, above this daemon's limit of " +
                                         number(limits.max_object_steps) + " (--max-run-object-steps)"};
  if (estimate.wall_hours > limits.max_wall_hours)
    return FieldError{duration_path, "the run would take about " + number(estimate.wall_hours) +
                                         " hours on one core, above this daemon's limit of " +
                                         number(limits.max_wall_hours) + " (--max-run-hours)"};
  const auto& c = scenario.conjunctions();
  if (c.has_screening_distance_km() && c.screening_distance_km() > limits.max_screening_km)
    return FieldError{"conjunctions.screening_distance_km",
                      "must be at most " + number(limits.max_screening_km) +
                          " km on this daemon (--max-screening-km), got " +
                          number(c.screening_distance_km())};
  return std::nullopt;
}

const char* const kRunLimitsUsage =
    R"(per-run limits, checked at submission from the scenario (INVALID_ARGUMENT above them):
  --max-run-objects N   objects a run simulates (default 2000000)
  --max-run-steps N     steps (duration / dt_s) (default 200000000)
  --max-run-object-steps X
                        objects x steps, the run's cost (default 2e13)
  --max-run-hours X     estimated wall time on one core, at 200 ns per object-step (default 720)
  --max-screening-km X  conjunctions.screening_distance_km (default 100)
  --max-run-events N    events a run may store; a run that emits more fails (default 50000000)
)";

bool parse_run_limit_flag(const std::string& flag, const std::string& value, RunLimits& limits,
                          std::string& error) {
  double* real = flag == "--max-run-object-steps" ? &limits.max_object_steps
                 : flag == "--max-run-hours"      ? &limits.max_wall_hours
                 : flag == "--max-screening-km"   ? &limits.max_screening_km
                                                  : nullptr;
  std::uint64_t* whole = flag == "--max-run-objects"  ? &limits.max_objects
                         : flag == "--max-run-steps"  ? &limits.max_steps
                         : flag == "--max-run-events" ? &limits.max_events
                                                      : nullptr;
  if (!real && !whole) return false;
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(value.c_str(), &end);
  const bool ok = !value.empty() && *end == '\0' && errno == 0 && std::isfinite(v) && v > 0.0 &&
                  (real || (v == std::floor(v) && v <= 1e18));
  if (!ok) {
    error = flag + " needs a positive " + (real ? "number" : "whole number");
    return true;
  }
  if (real)
    *real = v;
  else
    *whole = static_cast<std::uint64_t>(v);
  return true;
}

std::string EventLimitSink::failure() const {
  return "the run emitted more than " + std::to_string(max_events_) +
         " events, this daemon's limit per run (--max-run-events); it was stopped";
}

}  // namespace kessler::server
