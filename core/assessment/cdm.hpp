// A CCSDS Conjunction Data Message (CCSDS 508.0-B-1) as its keyword = value fields, section by section,
// in the message's order: what the KVN and XML readers produce and the writers take. Pure text in and
// out; reading files (and limiting their size) is the caller's business.
#pragma once

#include <array>
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace kessler::assessment {

struct CdmField {
  std::string keyword;   // "COMMENT" for comments
  std::string value;     // trimmed; a Unicode minus (U+2212) becomes '-'
  std::string unit;      // the [unit] in KVN, the units attribute in XML; empty when none
  std::size_t line = 0;  // 1-based line in the text read (0: built in memory)
};

struct Cdm {
  std::vector<CdmField> header;    // CCSDS_CDM_VERS, CREATION_DATE, ORIGINATOR, MESSAGE_FOR, MESSAGE_ID
  std::vector<CdmField> relative;  // relative metadata and data: TCA, MISS_DISTANCE, ...
  std::array<std::vector<CdmField>, 2> objects;  // OBJECT1 and OBJECT2: metadata, then data

  // The first field of that keyword in a section, or nullptr.
  static const CdmField* find(const std::vector<CdmField>& section, std::string_view keyword);
};

// A problem with a message: where (line, keyword) and why.
struct CdmError {
  std::size_t line = 0;
  std::string keyword;
  std::string message;  // "line 12, keyword MISS_DISTANCE: ..."
};

// The largest message the readers take: real CDMs are tens of kilobytes.
inline constexpr std::size_t kMaxCdmBytes = 4u << 20;

// KVN (keyword = value [unit] lines; CRLF or LF). Returns false with the errors when the text is not a
// CDM; a missing mandatory keyword is left to check_mandatory().
bool read_cdm_kvn(std::string_view text, Cdm& out, std::vector<CdmError>& errors);
// XML (the CCSDS NDM/XML layout). DOCTYPE and entity declarations are refused (no entity expansion).
bool read_cdm_xml(std::string_view text, Cdm& out, std::vector<CdmError>& errors);
// Either, by its first non-blank character ('<': XML).
bool read_cdm(std::string_view text, Cdm& out, std::vector<CdmError>& errors);

std::string write_cdm_kvn(const Cdm& cdm);
std::string write_cdm_xml(const Cdm& cdm);

// The standard's mandatory keywords, per section (the header's, the relative metadata's, each object's
// metadata, state vector and 6x6 RTN covariance), and the units of the keywords that carry one.
void check_mandatory(const Cdm& cdm, std::vector<CdmError>& errors);
void check_units(const Cdm& cdm, std::vector<CdmError>& errors);

// Which XML block a keyword belongs in ("header", "relativeStateVector", "metadata", "odParameters",
// "additionalParameters", "stateVector", "covarianceMatrix", or "" for the block itself).
std::string_view cdm_xml_block(std::string_view keyword);

// "line N, keyword K: message"
CdmError cdm_error(std::size_t line, std::string_view keyword, std::string_view message);

}  // namespace kessler::assessment
