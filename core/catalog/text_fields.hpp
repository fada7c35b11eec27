// Small strict parsers for fixed-column and delimited text fields, shared by the catalog readers. Each
// returns false (and leaves a reason) when the text is not what the field must hold, instead of reading
// a prefix as atof would.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace kessler::text {

std::string_view trim(std::string_view s);
// Removes a trailing '\r' (CRLF files) and trailing spaces.
std::string_view chomp(std::string_view s);
// Splits a text into lines (LF or CRLF), without the line ends.
std::vector<std::string_view> split_lines(std::string_view text);

// A decimal number: optional sign, digits with at most one '.', optional exponent (e/E). Surrounding
// spaces allowed. *reason says what is wrong when it returns false.
bool parse_double(std::string_view field, double& value, std::string* reason);
// An integer: optional sign and digits.
bool parse_int(std::string_view field, long long& value, std::string* reason);
// The TLE's implied-decimal form with exponent, e.g. " 12345-3" = 0.12345e-3, "-11606-4", "00000+0".
bool parse_implied_decimal(std::string_view field, double& value, std::string* reason);

// Upper-case copy (ASCII).
std::string upper(std::string_view s);

// 1-based line numbers of byte offsets into a text, asked in increasing order: each call counts on from
// the last, so numbering a whole catalog's records costs one pass (an earlier offset gets the last line).
class LineCounter {
 public:
  LineCounter(const char* text, std::size_t size) : text_(text), size_(size) {}
  std::size_t line_at(std::size_t offset) {
    const std::size_t end = offset < size_ ? offset : size_;
    for (; counted_to_ < end; ++counted_to_) line_ += text_[counted_to_] == '\n';
    return line_;
  }

 private:
  const char* text_;
  std::size_t size_;
  std::size_t counted_to_ = 0, line_ = 1;
};

}  // namespace kessler::text
