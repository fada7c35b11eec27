// Satellite catalogs (SATCAT) and active lists: where object types, radar cross sections and
// operational status come from.
//   Space-Track CSV: NORAD_CAT_ID, OBJECT_TYPE (PAYLOAD, ROCKET BODY, DEBRIS, UNKNOWN, TBA),
//     RCS_SIZE (SMALL, MEDIUM, LARGE), RCSVALUE (0 = none).
//   CelesTrak CSV: NORAD_CAT_ID, OBJECT_TYPE (PAY, R/B, DEB, UNK), OPS_STATUS_CODE, RCS [m^2].
// Files may be gzip-compressed (read_catalog_file decompresses).
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "core/catalog/parse_problem.hpp"
#include "core/population/population.hpp"
#include "core/time/epoch.hpp"

namespace kessler {

// Space-Track's RCS classes: small < 0.1 m^2, medium 0.1..1 m^2, large > 1 m^2.
enum class RcsSizeClass : std::uint8_t { kUnknown = 0, kSmall, kMedium, kLarge };
const char* rcs_size_class_name(RcsSizeClass c);
RcsSizeClass rcs_size_class_of(double rcs_m2);

struct SatcatEntry {
  ObjectId id = 0;
  std::string name;
  std::string object_type;  // normalised: PAYLOAD, ROCKET BODY, DEBRIS, UNKNOWN (or the text as given)
  RcsSizeClass size_class = RcsSizeClass::kUnknown;
  std::optional<double> rcs_m2;          // numeric RCS where the catalog has one (> 0)
  std::optional<char> ops_status_code;   // CelesTrak operational status code (+ - P B S X D ?)
  std::string international_designator;  // INTLDES / OBJECT_ID ("1997-051C")
  std::optional<UtcEpoch> decay;         // DECAY / DECAY_DATE: the day it re-entered (00:00 UTC)
  std::optional<UtcEpoch> debut;         // DEBUT (Space-Track): the day it entered the catalogue
};

struct SatcatTable {
  std::unordered_map<ObjectId, SatcatEntry> entries;
  std::vector<ParseProblem> problems;
  std::size_t rows = 0;
  std::string flavour;  // "space-track" or "celestrak"
};

SatcatTable parse_satcat_csv(std::string_view text, const std::string& source);

// The ids in an active list: any OMM (CSV, JSON, KVN) or TLE/3LE text of operated satellites. Records
// without a readable id are reported in *problems.
std::unordered_set<ObjectId> parse_active_list(std::string_view text, const std::string& source,
                                               std::vector<ParseProblem>* problems);

// Reads a whole file; gzip files (any name) are decompressed. nullopt with *error on failure.
std::optional<std::string> read_catalog_file(const std::string& path, std::string* error);

// True when the operational status code counts as active (+ operational, P partially, B backup,
// S spare, X extended mission).
bool is_active_status_code(char code);

// The population's type for a normalised SATCAT object type (TBA and anything else: kUnknown).
ObjectType object_type_from_satcat(const std::string& normalised_type);

}  // namespace kessler
