#include "core/catalog/csv.hpp"

#include "core/catalog/text_fields.hpp"

namespace kessler {

std::optional<std::size_t> CsvTable::column(std::string_view name) const {
  for (std::size_t i = 0; i < header.size(); ++i)
    if (header[i] == name) return i;
  return std::nullopt;
}

CsvTable parse_csv(std::string_view text, bool has_header) {
  CsvTable table;
  std::size_t pos = 0, line = 1;
  if (text.size() >= 3 && static_cast<unsigned char>(text[0]) == 0xEF) pos = 3;  // UTF-8 byte-order mark
  bool header_done = !has_header;
  while (pos < text.size()) {
    CsvRow row;
    row.line = line;
    std::string field;
    bool in_quotes = false, row_done = false;
    while (pos < text.size() && !row_done) {
      const char c = text[pos++];
      if (in_quotes) {
        if (c == '"') {
          if (pos < text.size() && text[pos] == '"') {
            field += '"';
            ++pos;
          } else {
            in_quotes = false;
          }
        } else {
          if (c == '\n') ++line;
          field += c;
        }
      } else if (c == '"') {
        in_quotes = true;
      } else if (c == ',') {
        row.fields.push_back(std::move(field));
        field.clear();
      } else if (c == '\n') {
        ++line;
        row_done = true;
      } else if (c != '\r') {
        field += c;
      }
    }
    row.fields.push_back(std::move(field));
    if (row.fields.size() == 1 && text::trim(row.fields[0]).empty()) continue;  // blank line
    if (!header_done) {
      for (auto& f : row.fields) table.header.push_back(text::upper(text::trim(f)));
      header_done = true;
    } else {
      table.rows.push_back(std::move(row));
    }
  }
  return table;
}

}  // namespace kessler
