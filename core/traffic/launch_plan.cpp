#include "core/traffic/launch_plan.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <numbers>

#include "core/catalog/csv.hpp"
#include "core/catalog/text_fields.hpp"
#include "core/random/counter_random.hpp"

namespace kessler {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;
constexpr double kYear_s = 365.25 * 86400.0;

const char* const kColumns[] = {
    "EPOCH",           "EPOCH_END", "COUNT",           "ALTITUDE_KM", "PERIGEE_KM", "APOGEE_KM",
    "INCLINATION_DEG", "RAAN_DEG",  "RAAN_SPREAD_DEG", "PLANES",      "PHASING",    "MASS_KG",
    "RADIUS_M",        "TYPE",      "LIFETIME_YEARS",  "MANOEUVRES",  "DEORBIT",    "LABEL"};

// The fields of one row by column name.
struct RowReader {
  const CsvTable& table;
  const CsvRow& row;

  std::optional<std::string> text(const char* column) const {
    const auto c = table.column(column);
    if (!c || *c >= row.fields.size()) return std::nullopt;
    std::string v(text::trim(row.fields[*c]));
    if (v.empty()) return std::nullopt;
    return v;
  }
  [[noreturn]] void fail(const char* column, const std::string& reason) const {
    std::string name = column;
    std::transform(name.begin(), name.end(), name.begin(), [](unsigned char ch) { return std::tolower(ch); });
    throw LaunchPlanError(row.line, name, reason);
  }
  std::optional<double> number(const char* column) const {
    const auto v = text(column);
    if (!v) return std::nullopt;
    double out = 0.0;
    const auto [end, ec] = std::from_chars(v->data(), v->data() + v->size(), out);
    if (ec != std::errc{} || end != v->data() + v->size() || !std::isfinite(out))
      fail(column, "not a number: '" + *v + "'");
    return out;
  }
  std::optional<std::uint64_t> whole(const char* column) const {
    const auto v = number(column);
    if (!v) return std::nullopt;
    if (*v < 0.0 || *v != std::floor(*v) || *v > 1e9) fail(column, "must be a whole number >= 0");
    return static_cast<std::uint64_t>(*v);
  }
  std::optional<bool> flag(const char* column) const {
    const auto v = text(column);
    if (!v) return std::nullopt;
    const std::string t = text::upper(*v);
    if (t == "TRUE" || t == "YES" || t == "1") return true;
    if (t == "FALSE" || t == "NO" || t == "0") return false;
    fail(column, "must be true or false, got '" + *v + "'");
  }
  UtcEpoch epoch(const char* column) const {
    const auto v = text(column);
    if (!v) fail(column, "is required");
    std::string error;
    const auto e = UtcEpoch::parse_iso8601(*v, &error);
    if (!e) fail(column, "not an ISO 8601 UTC time: '" + *v + "'");
    return *e;
  }
};

void read_orbit(const RowReader& r, LaunchRow& row) {
  const auto altitude = r.number("ALTITUDE_KM");
  const auto perigee = r.number("PERIGEE_KM"), apogee = r.number("APOGEE_KM");
  if (altitude && (perigee || apogee))
    r.fail("ALTITUDE_KM", "give altitude_km or perigee_km and apogee_km, not both");
  if (!altitude && !(perigee && apogee)) r.fail("ALTITUDE_KM", "is required (or perigee_km and apogee_km)");
  row.perigee_km = altitude ? *altitude : *perigee;
  row.apogee_km = altitude ? *altitude : *apogee;
  const char* column = altitude ? "ALTITUDE_KM" : "PERIGEE_KM";
  if (row.perigee_km < 100.0) r.fail(column, "below 100 km: the orbit would not survive launch");
  if (row.apogee_km > 40000.0)
    r.fail(altitude ? "ALTITUDE_KM" : "APOGEE_KM", "above 40,000 km, outside the domain");
  if (row.perigee_km > row.apogee_km) r.fail("PERIGEE_KM", "above apogee_km");
  const auto inc = r.number("INCLINATION_DEG");
  if (!inc) r.fail("INCLINATION_DEG", "is required");
  if (*inc < 0.0 || *inc > 180.0) r.fail("INCLINATION_DEG", "must lie in [0, 180]");
  row.inclination_deg = *inc;
}

LaunchRow read_row(const CsvTable& table, const CsvRow& csv_row) {
  const RowReader r{table, csv_row};
  LaunchRow row;
  row.line = csv_row.line;
  row.epoch = r.epoch("EPOCH");
  if (r.text("EPOCH_END")) {
    row.epoch_end = r.epoch("EPOCH_END");
    if (row.epoch_end->seconds_since(row.epoch) < 0.0) r.fail("EPOCH_END", "before epoch");
  }
  const auto count = r.whole("COUNT");
  if (!count || *count == 0) r.fail("COUNT", "must be a whole number >= 1");
  row.count = *count;
  read_orbit(r, row);
  row.raan_deg = r.number("RAAN_DEG");
  row.raan_spread_deg = r.number("RAAN_SPREAD_DEG").value_or(360.0);
  if (row.raan_spread_deg < 0.0 || row.raan_spread_deg > 360.0)
    r.fail("RAAN_SPREAD_DEG", "must lie in [0, 360]");
  row.planes = r.whole("PLANES").value_or(1);
  if (row.planes == 0 || row.count % row.planes != 0) r.fail("PLANES", "must divide count");
  row.phasing = r.whole("PHASING").value_or(0);
  if (const auto type = r.text("TYPE")) {
    const std::string t = text::upper(*type);
    if (t == "PAYLOAD")
      row.type = ObjectType::kPayload;
    else if (t == "ROCKET_BODY" || t == "ROCKET BODY")
      row.type = ObjectType::kRocketBody;
    else
      r.fail("TYPE", "must be payload or rocket_body, got '" + *type + "'");
  }
  const bool payload = row.type == ObjectType::kPayload;
  row.mass_kg = r.number("MASS_KG").value_or(payload ? 260.0 : 1500.0);
  row.radius_m = r.number("RADIUS_M").value_or(payload ? 1.5 : 2.0);
  if (!(row.mass_kg > 0.0)) r.fail("MASS_KG", "must be positive");
  if (!(row.radius_m > 0.0) || row.radius_m > 100.0) r.fail("RADIUS_M", "must lie in (0, 100] m");
  row.lifetime_years = r.number("LIFETIME_YEARS");
  if (row.lifetime_years && (*row.lifetime_years < 0.0 || *row.lifetime_years > 100.0))
    r.fail("LIFETIME_YEARS", "must lie in [0, 100]");
  row.manoeuvres = r.flag("MANOEUVRES").value_or(payload);
  row.deorbit = r.flag("DEORBIT").value_or(false);
  if (row.deorbit && payload) r.fail("DEORBIT", "only rocket bodies de-orbit at launch");
  row.label = r.text("LABEL").value_or("");
  return row;
}

}  // namespace

LaunchPlan parse_launch_plan_csv(std::string_view text) {
  const CsvTable table = parse_csv(text);
  for (std::size_t c = 0; c < table.header.size(); ++c)
    if (std::none_of(std::begin(kColumns), std::end(kColumns),
                     [&](const char* k) { return table.header[c] == k; })) {
      // Headers are read upper-cased; messages name columns in lower case, as the rows' do.
      std::string name = table.header[c];
      std::transform(name.begin(), name.end(), name.begin(),
                     [](unsigned char ch) { return std::tolower(ch); });
      throw LaunchPlanError(1, name, "unknown column");
    }
  LaunchPlan plan;
  for (const CsvRow& row : table.rows) plan.rows.push_back(read_row(table, row));
  return plan;
}

namespace {

// The row's object `index` at the row's own epoch (plus its share of epoch_end's spread).
PlannedObject plan_object(const LaunchRow& row, std::size_t row_index, std::uint64_t index,
                          std::uint64_t seed) {
  PlannedObject o;
  o.row = row_index;
  o.index = index;
  const std::uint64_t per_plane = row.count / row.planes;
  const std::uint64_t plane = index / per_plane, slot = index % per_plane;
  const double raan0 =
      row.raan_deg ? *row.raan_deg : 360.0 * random_uniform(seed, row_index, RandomPurpose::kLaunchOrbit, 0);
  OrbitElements el =
      elements_from_altitudes(row.perigee_km * 1e3, row.apogee_km * 1e3, row.inclination_deg * kDeg);
  el.raan_rad = std::remainder(
      (raan0 + row.raan_spread_deg * static_cast<double>(plane) / static_cast<double>(row.planes)) * kDeg,
      2.0 * std::numbers::pi);
  el.argument_of_perigee_rad =
      el.eccentricity > 0.0
          ? 2.0 * std::numbers::pi * random_uniform(seed, row_index, RandomPurpose::kLaunchOrbit, 1)
          : 0.0;
  el.mean_anomaly_rad = 2.0 * std::numbers::pi *
                        (static_cast<double>(slot) / static_cast<double>(per_plane) +
                         static_cast<double>(row.phasing * plane) / static_cast<double>(row.count));
  o.elements = el;
  const bool payload = row.type == ObjectType::kPayload;
  o.type = row.type;
  o.mass_kg = row.mass_kg;
  o.radius_m = row.radius_m;
  o.lifetime_s = payload ? row.lifetime_years.value_or(5.0) * kYear_s : 0.0;
  o.manoeuvres = payload && row.manoeuvres && o.lifetime_s > 0.0;
  return o;
}

}  // namespace

std::vector<PlannedObject> expand_launch_plan(const LaunchPlan& plan, const UtcEpoch& start,
                                              double duration_s, std::uint64_t seed) {
  std::vector<PlannedObject> out;
  for (std::size_t r = 0; r < plan.rows.size(); ++r) {
    const LaunchRow& row = plan.rows[r];
    if (row.deorbit) continue;
    const double t0 = row.epoch.seconds_since(start);
    const double t1 = row.epoch_end ? row.epoch_end->seconds_since(start) : t0;
    for (std::uint64_t k = 0; k < row.count; ++k) {
      const double share = row.count > 1 ? static_cast<double>(k) / static_cast<double>(row.count - 1) : 0.0;
      const double t = t0 + (t1 - t0) * share;
      if (t < 0.0 || t >= duration_s) continue;
      PlannedObject o = plan_object(row, r, k, seed);
      o.epoch_offset_s = t;
      out.push_back(o);
    }
  }
  std::stable_sort(out.begin(), out.end(), [](const PlannedObject& a, const PlannedObject& b) {
    return a.epoch_offset_s < b.epoch_offset_s;
  });
  return out;
}

}  // namespace kessler
