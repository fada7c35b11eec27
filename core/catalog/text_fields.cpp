#include "core/catalog/text_fields.hpp"

#include <cctype>
#include <charconv>
#include <cmath>

namespace kessler::text {

std::string_view trim(std::string_view s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
  return s;
}

std::string_view chomp(std::string_view s) {
  while (!s.empty() && (s.back() == '\r' || s.back() == ' ' || s.back() == '\n')) s.remove_suffix(1);
  return s;
}

std::vector<std::string_view> split_lines(std::string_view text) {
  std::vector<std::string_view> lines;
  std::size_t start = 0;
  while (start < text.size()) {
    std::size_t end = text.find('\n', start);
    if (end == std::string_view::npos) end = text.size();
    std::string_view line = text.substr(start, end - start);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    lines.push_back(line);
    start = end + 1;
  }
  return lines;
}

bool parse_double(std::string_view field, double& value, std::string* reason) {
  std::string_view s = trim(field);
  if (s.empty()) {
    if (reason) *reason = "empty";
    return false;
  }
  std::size_t i = 0;
  if (s[i] == '+' || s[i] == '-') ++i;
  bool digits = false, dot = false;
  for (; i < s.size(); ++i) {
    const char c = s[i];
    if (c >= '0' && c <= '9') {
      digits = true;
    } else if (c == '.' && !dot) {
      dot = true;
    } else if ((c == 'e' || c == 'E') && digits) {
      std::size_t j = i + 1;
      if (j < s.size() && (s[j] == '+' || s[j] == '-')) ++j;
      if (j == s.size()) break;
      for (; j < s.size(); ++j)
        if (s[j] < '0' || s[j] > '9') break;
      i = j;
      break;
    } else {
      break;
    }
  }
  if (i != s.size() || !digits) {
    if (reason) *reason = "not a number: '" + std::string(s) + "'";
    return false;
  }
  std::string copy(s.front() == '+' ? s.substr(1) : s);
  // The text is validated above; strtod reads it exactly (from_chars refuses a leading '.').
  value = std::strtod(copy.c_str(), nullptr);
  if (!std::isfinite(value)) {
    if (reason) *reason = "not a finite number: '" + std::string(s) + "'";
    return false;
  }
  return true;
}

bool parse_int(std::string_view field, long long& value, std::string* reason) {
  std::string_view s = trim(field);
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), value);
  if (s.empty() || ec != std::errc() || ptr != s.data() + s.size()) {
    if (reason) *reason = "not an integer: '" + std::string(trim(field)) + "'";
    return false;
  }
  return true;
}

bool parse_implied_decimal(std::string_view field, double& value, std::string* reason) {
  std::string_view s = trim(field);
  auto fail = [&]() {
    if (reason) *reason = "not an implied-decimal number such as ' 12345-3': '" + std::string(s) + "'";
    return false;
  };
  if (s.empty()) return fail();
  double sign = 1.0;
  if (s.front() == '-' || s.front() == '+') {
    sign = s.front() == '-' ? -1.0 : 1.0;
    s.remove_prefix(1);
  }
  if (!s.empty() && s.front() == '.') s.remove_prefix(1);  // some writers print the point
  std::size_t exp_pos = s.find_first_of("+-");
  std::string_view mantissa = s.substr(0, exp_pos);
  if (mantissa.empty()) return fail();
  for (char c : mantissa)
    if (c < '0' || c > '9') return fail();
  int exponent = 0;
  if (exp_pos != std::string_view::npos) {
    std::string_view e = s.substr(exp_pos + 1);
    if (e.empty()) return fail();
    for (char c : e) {
      if (c < '0' || c > '9') return fail();
      exponent = exponent * 10 + (c - '0');
    }
    if (s[exp_pos] == '-') exponent = -exponent;
  }
  // Same arithmetic as reading "0.<digits>e<exp>" as text, so values round as other readers do.
  std::string as_text = "0." + std::string(mantissa) + "e" + std::to_string(exponent);
  value = sign * std::strtod(as_text.c_str(), nullptr);
  return true;
}

std::string upper(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return out;
}

}  // namespace kessler::text
