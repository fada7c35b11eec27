// Two-line element sets (TLE) and three-line ones with a name line (3LE), as Space-Track and CelesTrak
// publish them: CRLF or LF line ends, unpadded catalog numbers, alpha-5 numbers (T0000 = 270000),
// checksums (modulo 10, '-' counts 1). Columns follow the NORAD format; anything past column 69 is
// ignored.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/catalog/parse_problem.hpp"
#include "core/sgp4/mean_elements.hpp"

namespace kessler {

struct TleReadOptions {
  bool verify_checksums = true;
};

// Decodes a catalog number field: digits (leading spaces allowed) or alpha-5 (a letter, I and O
// excluded, then four digits). nullopt when the field is neither.
std::optional<std::uint64_t> decode_catalog_number(std::string_view field);

// Modulo-10 checksum of the first 68 columns.
int tle_checksum(std::string_view line);

// One element set from its two lines. On failure returns nullopt with *problem filled (line set to 1
// or 2, the line within the record).
std::optional<MeanElements> parse_tle_lines(std::string_view line1, std::string_view line2,
                                            const TleReadOptions& options, ParseProblem* problem);

struct ElementSetEntry {
  MeanElements elements;
  std::size_t line = 0;  // 1-based line of the set's first line in the text (name line for 3LE)
};

struct ElementSetText {
  std::vector<ElementSetEntry> sets;
  std::vector<ParseProblem> problems;  // every record that was not accepted
};

// Every element set in a TLE or 3LE text (the two may mix: a line that is neither a line 1 nor a line 2
// is a name line; "0 " prefixes of 3LE names are removed). Bad records are reported, not dropped.
ElementSetText parse_tle_text(std::string_view text, const TleReadOptions& options,
                              const std::string& source);

}  // namespace kessler
