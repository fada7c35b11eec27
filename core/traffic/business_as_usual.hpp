// "Business as usual" launch traffic, the standard assumption of the IADC studies: the launches of the
// last N years repeat, with the same orbits, cycle after cycle.
#pragma once

#include <string_view>
#include <vector>

#include "core/sgp4/mean_elements.hpp"
#include "core/time/epoch.hpp"
#include "core/traffic/launch_plan.hpp"

namespace kessler {

// One launched object with its orbit.
struct LaunchRecord {
  ObjectId id = 0;
  UtcEpoch launch;
  ObjectType type = ObjectType::kPayload;
  double perigee_km = 0.0, apogee_km = 0.0, inclination_deg = 0.0;
};

// The payloads and rocket bodies of a Space-Track SATCAT CSV (columns NORAD_CAT_ID, OBJECT_TYPE,
// LAUNCH) that have an element set in `element_sets` (their orbit: perigee and apogee from the Kozai
// mean motion and eccentricity, as SGP4's a). Objects that have decayed have no set and are left out:
// the plan undercounts launches into short-lived orbits. Throws LaunchPlanError on a missing column.
std::vector<LaunchRecord> launch_records(std::string_view satcat_csv,
                                         const std::vector<MeanElements>& element_sets);

// Every record launched in [window_end - window_years, window_end) with perigee below 2,000 km,
// relaunched every window_years after its launch date from window_end until `until`: one row of count 1
// per launch, with the record's perigee, apogee and inclination, a drawn RAAN and the type's defaults
// (mass, radius, lifetime: launch_plan.hpp).
LaunchPlan business_as_usual_plan(const std::vector<LaunchRecord>& records, const UtcEpoch& window_end,
                                  double window_years, const UtcEpoch& until);

}  // namespace kessler
