// A launch plan: rows of launches and constellation deployments, read from CSV text, and the objects
// they put in orbit (core/traffic/README.md). Each row's objects enter the population at their epochs.
#pragma once

#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "core/population/population.hpp"
#include "core/time/epoch.hpp"
#include "core/traffic/orbit_elements.hpp"

namespace kessler {

// One row. The orbit: altitude_km (circular), or perigee_km and apogee_km. Planes: `planes` planes
// spread evenly over raan_spread_deg from raan_deg, count / planes objects each, evenly in mean anomaly,
// plane k shifted by phasing * k * 360 / count degrees (a Walker delta pattern i: T/P/F).
struct LaunchRow {
  std::size_t line = 0;  // in the plan's text, for messages
  UtcEpoch epoch;
  std::optional<UtcEpoch> epoch_end;  // objects spread evenly over [epoch, epoch_end] in plan order
  std::uint64_t count = 1;
  double perigee_km = 0.0, apogee_km = 0.0;
  double inclination_deg = 0.0;
  std::optional<double> raan_deg;  // unset: drawn (seed, row, kLaunchOrbit)
  double raan_spread_deg = 360.0;
  std::uint64_t planes = 1;
  std::uint64_t phasing = 0;
  double mass_kg = 0.0;   // 0: by type (payload 260 kg, rocket body 1,500 kg)
  double radius_m = 0.0;  // 0: by type (payload 1.5 m, rocket body 2.0 m)
  ObjectType type = ObjectType::kPayload;
  // Operational lifetime [years]: active (station-kept) for this long, then end of life. Rocket bodies
  // and lifetime 0: passive from launch.
  std::optional<double> lifetime_years;
  bool manoeuvres = true;  // active payloads evade and keep station
  bool deorbit = false;    // rocket bodies: de-orbited right after launch (they never join)
  std::string label;
};

struct LaunchPlan {
  std::vector<LaunchRow> rows;
};

// A plan the reader refuses: the 1-based line, the column and the reason.
class LaunchPlanError : public std::invalid_argument {
 public:
  LaunchPlanError(std::size_t line, const std::string& column, const std::string& reason)
      : std::invalid_argument("line " + std::to_string(line) + ": " + column + ": " + reason),
        line_(line),
        column_(column) {}
  std::size_t line() const { return line_; }
  const std::string& column() const { return column_; }

 private:
  std::size_t line_;
  std::string column_;
};

// Reads a plan from CSV with a header row. Columns (case-insensitive): epoch (ISO 8601 UTC), count,
// inclination_deg, and altitude_km or perigee_km and apogee_km, required; epoch_end, raan_deg,
// raan_spread_deg, planes, phasing, mass_kg, radius_m, type (payload | rocket_body), lifetime_years,
// manoeuvres (true | false), deorbit, label optional. Unknown columns, bad numbers, counts of 0 or not
// divisible by planes, orbits below 100 km or above 40,000 km, perigee above apogee: LaunchPlanError.
LaunchPlan parse_launch_plan_csv(std::string_view text);

// One object a plan puts in orbit.
struct PlannedObject {
  double epoch_offset_s = 0.0;  // seconds from the scenario start
  std::size_t row = 0;          // index into LaunchPlan::rows
  std::uint64_t index = 0;      // within its row
  OrbitElements elements;       // at epoch_offset_s
  double mass_kg = 0.0, radius_m = 0.0;
  ObjectType type = ObjectType::kPayload;
  double lifetime_s = 0.0;  // 0: passive from launch
  bool manoeuvres = false;
};

// Every object of the plan launched in [0, duration_s) after `start`, in (epoch, row, index) order.
// Random parts (a drawn RAAN; the argument of perigee of eccentric orbits) are keyed by (seed, row,
// purpose). Rows outside the span contribute nothing.
std::vector<PlannedObject> expand_launch_plan(const LaunchPlan& plan, const UtcEpoch& start,
                                              double duration_s, std::uint64_t seed);

}  // namespace kessler
