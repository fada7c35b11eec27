// CSV as catalogs write it (RFC 4180): comma separated, fields optionally in double quotes with ""
// for a quote, LF or CRLF rows. A header row names the columns.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace kessler {

struct CsvRow {
  std::size_t line = 0;  // 1-based line where the row starts
  std::vector<std::string> fields;
};

struct CsvTable {
  std::vector<std::string> header;  // upper-cased, trimmed
  std::vector<CsvRow> rows;
  // Index of a header column, if present.
  std::optional<std::size_t> column(std::string_view name) const;
};

// Splits a CSV text; the first non-empty row is the header when `has_header`.
CsvTable parse_csv(std::string_view text, bool has_header = true);

}  // namespace kessler
