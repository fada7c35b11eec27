// Catalog ingest: element sets (TLE/3LE, OMM CSV/JSON/KVN/XML) with an optional SATCAT and active list
// become a Population at the scenario's start epoch, by the paper's rules:
//   1. parse every record (bad ones rejected with line and reason; strict mode refuses the catalog);
//      element sets whose epoch lies more than max_epoch_after_start_days after the start are rejected;
//   2. filters, each object counted under the first it fails: excluded name (paper: ISS, Starlink,
//      OneWeb), object type, perigee/apogee altitude band of the mean elements (175..2000 km);
//   3. SGP4 to the start epoch (TEME); objects SGP4 cannot bring there are reported and left out, and so
//      are objects already below the burn-up altitude there (element sets older than their decay);
//   4. radius sqrt(RCS/pi) or sampled per RCS class (never below 5 mm), mass law, Cd A/m from BSTAR
//      (B* > 0) else Cd = 2.2 with pi r^2 / m, SRP A/m = pi r^2 / m; status active when the SATCAT
//      operational status is + P B S X or the object is on the active list.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/catalog/object_properties.hpp"
#include "core/catalog/parse_problem.hpp"
#include "core/catalog/tle.hpp"
#include "core/decay/ballistic_fit.hpp"
#include "core/population/population.hpp"
#include "core/sgp4/sgp4.hpp"
#include "core/time/epoch.hpp"

namespace kessler {

enum class CatalogFormat { kDetect, kTle, kOmmCsv, kOmmJson, kOmmKvn, kOmmXml };

// The format of a catalog text from its first characters.
CatalogFormat detect_catalog_format(std::string_view text);
const char* catalog_format_name(CatalogFormat format);
// Every element set of a text in the given (or detected) format.
ElementSetText parse_catalog_text(std::string_view text, CatalogFormat format, const std::string& source,
                                  const TleReadOptions& tle_options = {});

struct CatalogInput {
  CatalogFormat format = CatalogFormat::kDetect;
  std::string text;  // the element sets
  std::string source = "catalog";
  std::string satcat_csv;  // optional: Space-Track or CelesTrak SATCAT CSV
  std::string satcat_source = "satcat";
  std::string active_list;  // optional: OMM or TLE text of operated satellites
  std::string active_list_source = "active list";
};

struct IngestRules {
  // Lenient (false): skip and count bad records. Strict: one bad record refuses the catalog.
  bool strict = false;
  bool verify_checksums = true;
  // Perigee and apogee altitude band of the mean elements [km] (over the WGS-72 radius, 6378.135 km).
  double min_perigee_km = 175.0;
  double max_apogee_km = 2000.0;
  // Names to leave out: exact names or glob patterns (* and ?), case-insensitive.
  std::vector<std::string> exclude_names;
  bool default_exclusions = true;  // add paper_exclusions() to exclude_names
  // SATCAT object types to keep (PAYLOAD, ROCKET BODY, DEBRIS, UNKNOWN). Empty: all.
  std::vector<std::string> object_types;
  // Element sets with an epoch more than this after the start epoch are rejected [days].
  double max_epoch_after_start_days = 30.0;
  SizeSampling sizes;
  double drag_coefficient = 2.2;
  // A vehicle docked to a station is catalogued with a copy of the station's element set: both would sit
  // at the same point and "collide" once per orbit. Drop every element set identical (epoch and all mean
  // elements) to an earlier record's, reported as "docked".
  bool drop_docked = true;
  // Objects whose SGP4 position at the start epoch is already below this altitude [km] over the
  // equatorial radius (the simulation's burn-up test, burns_up) have decayed before the start: left out
  // as "decayed before the start" instead of burning up at the first step. The scenario's burn-up altitude.
  double burn_up_altitude_km = 150.0;
  // Keep at most this many objects, in catalog order (0: all).
  std::uint64_t max_objects = 0;

  // The paper's exclusions: the ISS (every module catalogued under its name), Starlink and OneWeb.
  static std::vector<std::string> paper_exclusions() { return {"ISS (*)", "STARLINK*", "ONEWEB*"}; }
};

// Statistics of one status group, for the report and the validation.
struct GroupSummary {
  std::size_t count = 0;
  double median_radius_m = 0.0;
  double median_mass_kg = 0.0;
  double median_semi_major_axis_km = 0.0;  // of the mean elements
};

struct IngestReport {
  std::string source;
  std::string format;
  UtcEpoch start_epoch;
  // Catalog records.
  std::size_t records = 0;
  std::size_t accepted = 0;
  std::size_t rejected = 0;
  std::vector<ParseProblem> rejections;
  std::map<std::string, std::size_t> rejected_by_reason;
  // Accepted element sets left out by the rules, by reason (each object counted once, under the first
  // rule it fails), and the objects SGP4 could not bring to the start epoch (also counted in
  // filtered_by_reason, as "SGP4 failed" or "invalid state"). Hence
  //   records == kept + rejected + the sum of filtered_by_reason.
  std::vector<std::pair<std::string, std::size_t>> filtered_by_reason;
  std::vector<std::pair<ObjectId, std::string>> propagation_failures;
  std::size_t kept = 0, active = 0, passive = 0;
  // Where the properties came from.
  std::size_t radius_from_rcs = 0, radius_sampled = 0, radius_sampled_unknown_class = 0;
  std::size_t drag_from_bstar = 0, drag_from_size = 0;
  // Ballistic coefficients fitted in the run's atmosphere after the ingest (core/decay/), when the
  // scenario asks for them (the run builder fills this); they replace the two rules above per object.
  std::optional<BallisticFitCounts> drag_fit;
  std::size_t active_by_status_code = 0, active_by_list = 0;
  // Side inputs.
  std::size_t satcat_rows = 0, satcat_matched = 0, active_list_ids = 0;
  std::vector<ParseProblem> side_input_problems;
  GroupSummary active_summary, passive_summary;

  std::size_t filtered(const std::string& reason) const;
  // A readable rendering; at most max_listed rejections and failures are listed one by one.
  std::string text(std::size_t max_listed = 20) const;
};

struct IngestResult {
  bool refused = false;  // strict mode met a bad record: population empty, error says why
  std::string error;
  Population population;                        // at the start epoch, TEME, m and m/s
  std::vector<MeanElements> elements;           // index-aligned with population (as it was ingested)
  std::vector<Sgp4Record> sgp4_records;         // index-aligned with population
  std::vector<double> mean_semi_major_axis_km;  // index-aligned with population
  IngestReport report;
};

IngestResult ingest_catalog(const CatalogInput& input, const IngestRules& rules, const UtcEpoch& start_epoch,
                            std::uint64_t seed);

// Glob match (* any run, ? one character), case-insensitive.
bool glob_match(std::string_view pattern, std::string_view text);

}  // namespace kessler
