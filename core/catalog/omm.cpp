#include "core/catalog/omm.hpp"

#include <cmath>

#include "core/catalog/csv.hpp"
#include "core/catalog/text_fields.hpp"

namespace kessler {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDegToRad = kPi / 180.0;

bool digits(std::string_view s, std::size_t pos, std::size_t n, int& out) {
  if (pos + n > s.size()) return false;
  out = 0;
  for (std::size_t i = pos; i < pos + n; ++i) {
    if (s[i] < '0' || s[i] > '9') return false;
    out = out * 10 + (s[i] - '0');
  }
  return true;
}

void add_problem(ElementSetText& out, const std::string& source, std::size_t line, ParseProblem p) {
  p.source = source;
  p.line = line;
  out.problems.push_back(std::move(p));
}

}  // namespace

void add_omm_fields(ElementSetText& out, const std::string& source, std::size_t line,
                    const std::map<std::string, std::string>& fields) {
  ParseProblem problem;
  if (auto el = elements_from_omm_fields(fields, &problem)) {
    out.sets.push_back({std::move(*el), line});
  } else {
    auto id = fields.find("NORAD_CAT_ID");
    if (id != fields.end()) problem.message = "NORAD_CAT_ID " + id->second + ", " + problem.message;
    add_problem(out, source, line, std::move(problem));
  }
}

std::optional<UtcEpoch> parse_omm_epoch(std::string_view text, std::string* error) {
  std::string_view s = text::trim(text);
  int year = 0, doy = 0;
  // Day-of-year form: YYYY-DDDT...
  if (s.size() >= 8 && digits(s, 0, 4, year) && s[4] == '-' && digits(s, 5, 3, doy) &&
      (s.size() == 8 || s[8] == 'T' || s[8] == ' ')) {
    int hour = 0, minute = 0;
    double second = 0.0;
    if (s.size() > 8) {
      std::string why;
      if (!digits(s, 9, 2, hour) || s.size() < 15 || s[11] != ':' || !digits(s, 12, 2, minute) ||
          s[14] != ':' ||
          !text::parse_double(s.substr(15, s.back() == 'Z' ? s.size() - 16 : std::string_view::npos), second,
                              &why)) {
        if (error) *error = "not a day-of-year epoch YYYY-DDDThh:mm:ss: '" + std::string(s) + "'";
        return std::nullopt;
      }
    }
    if (doy < 1 || doy > 366) {
      if (error) *error = "day of year outside 1..366: '" + std::string(s) + "'";
      return std::nullopt;
    }
    return UtcEpoch::from_year_and_day_of_year(year,
                                               doy + (hour * 3600.0 + minute * 60.0 + second) / 86400.0);
  }
  return UtcEpoch::parse_iso8601(s, error);
}

std::optional<MeanElements> elements_from_omm_fields(const std::map<std::string, std::string>& f,
                                                     ParseProblem* problem) {
  auto fail = [&](const char* key, const std::string& msg) -> std::optional<MeanElements> {
    if (problem) {
      problem->reason_key = key;
      problem->message = msg;
    }
    return std::nullopt;
  };
  auto get = [&](const char* name) -> const std::string* {
    auto it = f.find(name);
    return it == f.end() || text::trim(it->second).empty() ? nullptr : &it->second;
  };
  std::string why;
  auto number = [&](const char* name, double& out, bool required, double fallback) -> bool {
    const std::string* v = get(name);
    if (!v) {
      if (required) {
        why = std::string(name) + ": missing";
        return false;
      }
      out = fallback;
      return true;
    }
    // Some writers add units in brackets after the value ("1.0027 [rev/day]").
    std::string_view s = *v;
    if (auto b = s.find('['); b != std::string_view::npos) s = s.substr(0, b);
    if (!text::parse_double(s, out, &why)) {
      why = std::string(name) + ": " + why;
      return false;
    }
    return true;
  };

  MeanElements el;
  // SGP4 mean elements only: SGP4-XP (ephemeris type 4) uses other elements and drag terms.
  if (const std::string* theory = get("MEAN_ELEMENT_THEORY")) {
    const std::string t = text::upper(*theory);
    if (t.find("SGP") == std::string::npos || t.find("XP") != std::string::npos)
      return fail("theory", "MEAN_ELEMENT_THEORY '" + *theory + "' is not SGP4");
  }
  if (const std::string* type = get("EPHEMERIS_TYPE"); type && text::trim(*type) != "0")
    return fail("theory", "EPHEMERIS_TYPE " + *type + " is not SGP4 (0)");
  const std::string* id = get("NORAD_CAT_ID");
  if (!id) return fail("missing", "NORAD_CAT_ID: missing");
  auto catalog = decode_catalog_number(*id);
  if (!catalog) {
    long long n = 0;
    if (!text::parse_int(*id, n, &why) || n < 0)
      return fail("number", "NORAD_CAT_ID: not a catalog number: '" + *id + "'");
    catalog = static_cast<std::uint64_t>(n);
  }
  el.catalog_number = *catalog;
  if (const std::string* name = get("OBJECT_NAME")) el.name = std::string(text::trim(*name));
  if (const std::string* des = get("OBJECT_ID")) el.international_designator = std::string(text::trim(*des));
  const std::string* epoch_text = get("EPOCH");
  if (!epoch_text) return fail("missing", "EPOCH: missing");
  auto epoch = parse_omm_epoch(*epoch_text, &why);
  if (!epoch) return fail("epoch", "EPOCH: " + why);
  el.epoch = *epoch;

  double n = 0, e = 0, i = 0, raan = 0, argp = 0, m = 0, bstar = 0, ndot = 0, nddot = 0;
  if (!number("MEAN_MOTION", n, true, 0) || !number("ECCENTRICITY", e, true, 0) ||
      !number("INCLINATION", i, true, 0) || !number("RA_OF_ASC_NODE", raan, true, 0) ||
      !number("ARG_OF_PERICENTER", argp, true, 0) || !number("MEAN_ANOMALY", m, true, 0) ||
      !number("BSTAR", bstar, false, 0) || !number("MEAN_MOTION_DOT", ndot, false, 0) ||
      !number("MEAN_MOTION_DDOT", nddot, false, 0))
    return fail(why.find("missing") != std::string::npos ? "missing" : "number", why);
  if (e < 0.0 || e >= 1.0)
    return fail("eccentricity", "ECCENTRICITY: " + std::to_string(e) + " outside 0 <= e < 1");
  if (n <= 0.0) return fail("range", "MEAN_MOTION: " + std::to_string(n) + " rev/day not positive");
  if (i < 0.0 || i > 180.0) return fail("range", "INCLINATION: " + std::to_string(i) + " deg outside 0..180");

  el.mean_motion_rad_min = n / (1440.0 / (2.0 * kPi));
  el.eccentricity = e;
  el.inclination_rad = i * kDegToRad;
  el.raan_rad = raan * kDegToRad;
  el.argument_of_perigee_rad = argp * kDegToRad;
  el.mean_anomaly_rad = m * kDegToRad;
  el.bstar_per_earth_radius = bstar;
  el.mean_motion_dot_rad_min2 = ndot * (2.0 * kPi / 1440.0) / 1440.0;
  el.mean_motion_ddot_rad_min3 = nddot * (2.0 * kPi / 1440.0) / (1440.0 * 1440.0);
  return el;
}

ElementSetText parse_omm_csv(std::string_view text, const std::string& source) {
  ElementSetText out;
  const CsvTable table = parse_csv(text);
  for (const CsvRow& row : table.rows) {
    if (row.fields.size() != table.header.size()) {
      add_problem(out, source, row.line,
                  {"", 0, "columns",
                   std::to_string(row.fields.size()) + " fields, the header has " +
                       std::to_string(table.header.size())});
      continue;
    }
    std::map<std::string, std::string> fields;
    for (std::size_t c = 0; c < row.fields.size(); ++c) fields[table.header[c]] = row.fields[c];
    add_omm_fields(out, source, row.line, fields);
  }
  return out;
}

ElementSetText parse_omm_kvn(std::string_view text, const std::string& source) {
  ElementSetText out;
  std::map<std::string, std::string> fields;
  std::size_t message_line = 0, line_no = 0;
  auto flush = [&]() {
    if (!fields.empty()) add_omm_fields(out, source, message_line, fields);
    fields.clear();
  };
  for (std::string_view raw : text::split_lines(text)) {
    ++line_no;
    std::string_view line = text::trim(raw);
    if (line.empty() || line.rfind("COMMENT", 0) == 0) continue;
    const std::size_t eq = line.find('=');
    if (eq == std::string_view::npos) continue;  // block markers such as META_START
    const std::string key = text::upper(text::trim(line.substr(0, eq)));
    std::string value(text::trim(line.substr(eq + 1)));
    if (key == "CCSDS_OMM_VERS") {
      flush();
      message_line = line_no;
    }
    if (message_line == 0) message_line = line_no;
    fields[key] = value;
  }
  flush();
  return out;
}

}  // namespace kessler
