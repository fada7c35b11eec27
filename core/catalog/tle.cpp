#include "core/catalog/tle.hpp"

#include <cmath>

#include "core/catalog/text_fields.hpp"

namespace kessler {
namespace {

constexpr double kDegToRad = 3.14159265358979323846 / 180.0;
constexpr double kRevPerDayToRadPerMin = 2.0 * 3.14159265358979323846 / 1440.0;

bool is_line(std::string_view line, char first) {
  return line.size() >= 2 && line[0] == first && line[1] == ' ';
}

}  // namespace

std::optional<std::uint64_t> decode_catalog_number(std::string_view field) {
  std::string_view s = text::trim(field);
  if (s.empty() || s.size() > 5) return std::nullopt;
  std::uint64_t value = 0;
  std::size_t i = 0;
  if (s[0] >= 'A' && s[0] <= 'Z') {
    if (s.size() != 5 || s[0] == 'I' || s[0] == 'O') return std::nullopt;
    // Alpha-5: A=10 .. H=17, J=18 .. N=22, P=23 .. Z=33 (I and O are skipped).
    int letter = s[0] - 'A' + 10;
    if (s[0] > 'I') --letter;
    if (s[0] > 'O') --letter;
    value = static_cast<std::uint64_t>(letter);
    i = 1;
  }
  for (; i < s.size(); ++i) {
    if (s[i] < '0' || s[i] > '9') return std::nullopt;
    value = value * 10 + static_cast<std::uint64_t>(s[i] - '0');
  }
  return value;
}

int tle_checksum(std::string_view line) {
  int sum = 0;
  for (std::size_t i = 0; i < 68 && i < line.size(); ++i) {
    const char c = line[i];
    if (c >= '0' && c <= '9') sum += c - '0';
    if (c == '-') sum += 1;
  }
  return sum % 10;
}

std::optional<MeanElements> parse_tle_lines(std::string_view line1, std::string_view line2,
                                            const TleReadOptions& options, ParseProblem* problem) {
  auto fail = [&](int which, const char* key, const std::string& message) -> std::optional<MeanElements> {
    if (problem) {
      problem->line = static_cast<std::size_t>(which);
      problem->reason_key = key;
      problem->message = "line " + std::to_string(which) + ": " + message;
    }
    return std::nullopt;
  };
  line1 = text::chomp(line1);
  line2 = text::chomp(line2);
  const std::size_t min_length = options.verify_checksums ? 69 : 68;
  if (!is_line(line1, '1')) return fail(1, "format", "does not start with '1 '");
  if (!is_line(line2, '2')) return fail(2, "format", "does not start with '2 '");
  if (line1.size() < min_length)
    return fail(1, "truncated", "truncated: " + std::to_string(line1.size()) + " columns, expected 69");
  if (line2.size() < min_length)
    return fail(2, "truncated", "truncated: " + std::to_string(line2.size()) + " columns, expected 69");
  if (options.verify_checksums) {
    for (int which = 1; which <= 2; ++which) {
      std::string_view line = which == 1 ? line1 : line2;
      const char c = line[68];
      if (c < '0' || c > '9') return fail(which, "checksum", "checksum column 69 is not a digit");
      if (c - '0' != tle_checksum(line))
        return fail(which, "checksum",
                    "checksum mismatch: column 69 says " + std::string(1, c) + ", computed " +
                        std::to_string(tle_checksum(line)));
    }
  }

  MeanElements el;
  std::string why;
  auto number = [&](std::string_view line, std::size_t col, std::size_t len, const char* name, double& out,
                    int which) {
    if (!text::parse_double(line.substr(col, len), out, &why)) {
      why = std::string(name) + " (columns " + std::to_string(col + 1) + "-" + std::to_string(col + len) +
            "): " + why;
      fail(which, "number", why);
      return false;
    }
    return true;
  };

  const auto catalog1 = decode_catalog_number(line1.substr(2, 5));
  if (!catalog1)
    return fail(1, "number",
                "catalog number (columns 3-7) is not a number: '" + std::string(line1.substr(2, 5)) + "'");
  const auto catalog2 = decode_catalog_number(line2.substr(2, 5));
  if (!catalog2)
    return fail(2, "number",
                "catalog number (columns 3-7) is not a number: '" + std::string(line2.substr(2, 5)) + "'");
  if (*catalog1 != *catalog2)
    return fail(2, "mismatch",
                "catalog number " + std::to_string(*catalog2) + " differs from line 1's " +
                    std::to_string(*catalog1));
  el.catalog_number = *catalog1;
  el.international_designator = std::string(text::trim(line1.substr(9, 8)));

  long long year = 0;
  if (!text::parse_int(line1.substr(18, 2), year, &why))
    return fail(1, "number", "epoch year (columns 19-20): " + why);
  double day = 0.0;
  if (!number(line1, 20, 12, "epoch day", day, 1)) return std::nullopt;
  if (day < 1.0 || day >= 367.0)
    return fail(1, "range", "epoch day " + std::to_string(day) + " outside 1..366");
  el.epoch = UtcEpoch::from_year_and_day_of_year(static_cast<int>(year), day);

  double ndot = 0.0, nddot = 0.0, bstar = 0.0;
  if (!number(line1, 33, 10, "mean motion derivative", ndot, 1)) return std::nullopt;
  if (!text::parse_implied_decimal(line1.substr(44, 8), nddot, &why))
    return fail(1, "number", "mean motion second derivative (columns 45-52): " + why);
  if (!text::parse_implied_decimal(line1.substr(53, 8), bstar, &why))
    return fail(1, "number", "BSTAR (columns 54-61): " + why);

  double incl = 0, raan = 0, argp = 0, mean_anomaly = 0, mean_motion = 0;
  if (!number(line2, 8, 8, "inclination", incl, 2)) return std::nullopt;
  if (!number(line2, 17, 8, "right ascension of the node", raan, 2)) return std::nullopt;
  std::string ecc_digits(line2.substr(26, 7));
  for (char& c : ecc_digits)
    if (c == ' ') c = '0';
  double ecc = 0.0;
  for (char c : ecc_digits)
    if (c < '0' || c > '9')
      return fail(2, "number",
                  "eccentricity (columns 27-33) is not digits: '" + std::string(line2.substr(26, 7)) + "'");
  ecc = std::strtod(("0." + ecc_digits).c_str(), nullptr);
  if (!number(line2, 34, 8, "argument of perigee", argp, 2)) return std::nullopt;
  if (!number(line2, 43, 8, "mean anomaly", mean_anomaly, 2)) return std::nullopt;
  if (!number(line2, 52, 11, "mean motion", mean_motion, 2)) return std::nullopt;
  if (incl < 0.0 || incl > 180.0)
    return fail(2, "range", "inclination " + std::to_string(incl) + " deg outside 0..180");
  if (mean_motion <= 0.0)
    return fail(2, "range", "mean motion " + std::to_string(mean_motion) + " rev/day not positive");

  el.inclination_rad = incl * kDegToRad;
  el.raan_rad = raan * kDegToRad;
  el.eccentricity = ecc;
  el.argument_of_perigee_rad = argp * kDegToRad;
  el.mean_anomaly_rad = mean_anomaly * kDegToRad;
  el.mean_motion_rad_min = mean_motion / (1440.0 / (2.0 * 3.14159265358979323846));
  el.bstar_per_earth_radius = bstar;
  el.mean_motion_dot_rad_min2 = ndot * kRevPerDayToRadPerMin / 1440.0;
  el.mean_motion_ddot_rad_min3 = nddot * kRevPerDayToRadPerMin / (1440.0 * 1440.0);
  return el;
}

ElementSetText parse_tle_text(std::string_view text, const TleReadOptions& options,
                              const std::string& source) {
  ElementSetText out;
  const auto lines = text::split_lines(text);
  std::string pending_name;
  std::size_t name_line = 0;
  std::size_t i = 0;
  while (i < lines.size()) {
    const std::string_view line = text::chomp(lines[i]);
    if (text::trim(line).empty() || line.front() == '#') {
      ++i;
      continue;
    }
    if (is_line(line, '1')) {
      const std::size_t first_line = name_line ? name_line : i + 1;
      ParseProblem problem;
      problem.source = source;
      if (i + 1 >= lines.size() || !is_line(text::chomp(lines[i + 1]), '2')) {
        problem.line = i + 1;
        problem.reason_key = "truncated";
        problem.message = "line 1 of an element set without its line 2";
        out.problems.push_back(problem);
        ++i;
      } else {
        auto el = parse_tle_lines(line, lines[i + 1], options, &problem);
        if (el) {
          el->name = pending_name;
          out.sets.push_back({std::move(*el), first_line});
        } else {
          problem.line = i + problem.line;  // record line 1 or 2 -> file line
          problem.message =
              std::string("catalog number ") +
              std::string(text::trim(line.substr(2, std::min<std::size_t>(5, line.size() - 2)))) + ", " +
              problem.message;
          out.problems.push_back(problem);
        }
        i += 2;
      }
      pending_name.clear();
      name_line = 0;
      continue;
    }
    if (is_line(line, '2')) {
      out.problems.push_back({source, i + 1, "truncated", "line 2 of an element set without its line 1"});
      pending_name.clear();
      name_line = 0;
      ++i;
      continue;
    }
    // A name line (3LE): "0 NAME" or a bare name.
    std::string_view name = line;
    if (name.size() >= 2 && name[0] == '0' && name[1] == ' ') name.remove_prefix(2);
    pending_name = std::string(text::trim(name));
    name_line = i + 1;
    ++i;
  }
  return out;
}

}  // namespace kessler
