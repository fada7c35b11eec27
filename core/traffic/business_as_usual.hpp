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
  // > 0: the object decayed this many years after its launch, before the catalog's epoch, so no orbit
  // of it is known: perigee and apogee are 0 and the plan gives it a circular orbit that decays in that
  // time (business_as_usual_plan).
  double lived_years = 0.0;
};

// The payloads and rocket bodies of a Space-Track SATCAT CSV (columns NORAD_CAT_ID, OBJECT_TYPE,
// LAUNCH; INTLDES and DECAY when present) with their orbits. An object with an element set in
// `element_sets` has its orbit: perigee and apogee from the Kozai mean motion and eccentricity, as SGP4's
// a. One that decayed (a DECAY date after its launch) has no set: it is kept with lived_years and the
// inclination of the first object of the same launch (INTLDES year and number) with a set and a perigee
// below 2,000 km, and left out when its launch has no such object. Throws LaunchPlanError on a missing
// column.
std::vector<LaunchRecord> launch_records(std::string_view satcat_csv,
                                         const std::vector<MeanElements>& element_sets);

// The circular altitude [km] at which an object of `type` launched at inclination_deg (with the type's
// default mass and radius, Cd 2.2) decays to 150 km in lived_years in the standard density table
// (disposal_altitude_m, lifecycle.hpp); at least 160 km, at most 2,000 km.
double altitude_for_lifetime_km(double lived_years, double inclination_deg, ObjectType type);

// Every record launched in [window_end - window_years, window_end) with perigee below 2,000 km,
// relaunched every window_years after its launch date from window_end until `until`: one row of count 1
// per launch, with the record's perigee, apogee and inclination, a drawn RAAN and the type's defaults
// (mass, radius, lifetime: launch_plan.hpp). A decayed record (lived_years) is relaunched passive on the
// circular orbit of altitude_for_lifetime_km, so that its copy lives about as long as it did.
LaunchPlan business_as_usual_plan(const std::vector<LaunchRecord>& records, const UtcEpoch& window_end,
                                  double window_years, const UtcEpoch& until);

}  // namespace kessler
