// Orbit Mean-elements Messages (CCSDS 502.0) with SGP4 mean elements: CelesTrak's CSV and JSON forms
// and the CCSDS key = value (KVN) and XML forms. Angles in degrees and mean motion in rev/day, as
// published. omm.cpp: epochs, fields, CSV and KVN; omm_json.cpp (simdjson); omm_xml.cpp (pugixml).
#pragma once

#include <map>
#include <optional>
#include <string>
#include <string_view>

#include "core/catalog/parse_problem.hpp"
#include "core/catalog/tle.hpp"

namespace kessler {

// An OMM epoch: "YYYY-MM-DDThh:mm:ss[.f]" or the day-of-year form "YYYY-DDDThh:mm:ss[.f]" (Z optional).
std::optional<UtcEpoch> parse_omm_epoch(std::string_view text, std::string* error);

// Mean elements from OMM fields keyed by their upper-case names (EPOCH, MEAN_MOTION, ECCENTRICITY,
// INCLINATION, RA_OF_ASC_NODE, ARG_OF_PERICENTER, MEAN_ANOMALY, NORAD_CAT_ID, BSTAR, ...).
std::optional<MeanElements> elements_from_omm_fields(const std::map<std::string, std::string>& fields,
                                                     ParseProblem* problem);

// One message's fields (as elements_from_omm_fields takes them) into `out`: its element set, or a problem
// at `line` naming the NORAD_CAT_ID where there is one.
void add_omm_fields(ElementSetText& out, const std::string& source, std::size_t line,
                    const std::map<std::string, std::string>& fields);

ElementSetText parse_omm_csv(std::string_view text, const std::string& source);
// An array of flat objects, or one object; keys matched case-insensitively, nested values ignored. JSON
// that does not parse yields one problem (reason "json") naming the record, field and line, and no sets.
ElementSetText parse_omm_json(std::string_view text, const std::string& source);
// One or more KVN messages; each CCSDS_OMM_VERS line starts a new one.
ElementSetText parse_omm_kvn(std::string_view text, const std::string& source);
// CCSDS OMM XML (NDM/XML, as CelesTrak and the CCSDS examples write it): every <omm> element is one
// message; its leaf elements (<EPOCH>, <MEAN_MOTION>, ...) are the fields. Malformed XML, a DOCTYPE
// (entity declarations) or elements nested deeper than 64 levels yield one problem (reason "xml") with
// the line and the reason, and no sets.
ElementSetText parse_omm_xml(std::string_view text, const std::string& source);

}  // namespace kessler
