// The scenario's `traffic` block: its checks (field paths, before the run), the plans shipped with the
// project, and its mapping onto the core's TrafficSettings. Used by scenario_validation.cpp and
// run_builder.cpp.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <string_view>

#include "core/scenario/run_builder.hpp"
#include "core/simulation/traffic.hpp"
#include "core/time/epoch.hpp"
#include "core/traffic/launch_plan.hpp"

namespace kessler {

// The launch plans shipped in deploy/traffic/ (<name>.csv), by the names traffic.plans takes.
inline constexpr std::array<std::string_view, 3> kShippedPlans = {"starlink-gen1", "oneweb-phase1", "kuiper"};

// The file of a shipped plan in `traffic_dir` (BuildOptions::traffic_dir).
std::string shipped_plan_path(std::string_view name, const std::string& traffic_dir);

// Range and consistency checks of scenario.traffic that need no files: the inline plan parses, the plan
// names are shipped ones (each once), the numbers are in range, the propagator can move launched objects.
std::optional<FieldError> validate_traffic(const v1::Scenario& scenario);

// The settings of a valid traffic block without its launches (enabled, disposal), unset fields at their
// defaults. TrafficSettings::launches needs files: traffic_launches_of.
TrafficSettings traffic_settings_of(const v1::Traffic& traffic);

// Where the launches' sources live: the shipped plans and the bundled catalog (business as usual).
struct TrafficSources {
  std::string traffic_dir;
  std::string datasets_dir;
};

// The one plan of every source, rows concatenated in order: the inline CSV's rows, the named plans' rows
// in the listed order, then business as usual (window ending at window_end, relaunches until `until`).
std::optional<FieldError> traffic_plan_of(const v1::Traffic& traffic, const UtcEpoch& start,
                                          const UtcEpoch& until, const TrafficSources& sources,
                                          LaunchPlan& out);

// The objects a valid scenario's traffic launches within its run (expand_launch_plan of traffic_plan_of,
// with the scenario's start, duration and seed); empty when traffic is off. Errors: unreadable files.
std::optional<FieldError> traffic_launches_of(const v1::Scenario& scenario, const SimulationConfig& config,
                                              const TrafficSources& sources, std::vector<PlannedObject>& out);

}  // namespace kessler
