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

}  // namespace kessler::text
