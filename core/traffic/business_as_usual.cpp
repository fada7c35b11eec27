#include "core/traffic/business_as_usual.hpp"

#include <charconv>
#include <cmath>
#include <numbers>
#include <optional>
#include <string>
#include <unordered_map>

#include "core/catalog/csv.hpp"
#include "core/catalog/object_properties.hpp"
#include "core/catalog/text_fields.hpp"
#include "core/physics/atmosphere.hpp"
#include "core/sgp4/wgs72.hpp"
#include "core/traffic/lifecycle.hpp"

namespace kessler {
namespace {

constexpr double kYear_s = 365.25 * 86400.0;
// The types' defaults for a relaunched object.
constexpr double kPayloadMass_kg = 260.0, kPayloadRadius_m = 1.5;
constexpr double kRocketBodyMass_kg = 1500.0, kRocketBodyRadius_m = 2.0;

}  // namespace

std::vector<LaunchRecord> launch_records(std::string_view satcat_csv,
                                         const std::vector<MeanElements>& element_sets) {
  std::unordered_map<ObjectId, const MeanElements*> by_id;
  for (const MeanElements& el : element_sets) by_id[el.catalog_number] = &el;
  const CsvTable table = parse_csv(satcat_csv);
  const char* const needed[] = {"NORAD_CAT_ID", "OBJECT_TYPE", "LAUNCH"};
  std::size_t col[3];
  for (int k = 0; k < 3; ++k) {
    const auto c = table.column(needed[k]);
    if (!c) throw LaunchPlanError(1, needed[k], "the SATCAT has no such column");
    col[k] = *c;
  }
  const std::optional<std::size_t> designator_col = table.column("INTLDES"),
                                   decay_col = table.column("DECAY");
  auto field = [](const CsvRow& row, std::optional<std::size_t> c) {
    return c && *c < row.fields.size() ? text::trim(row.fields[*c]) : std::string_view();
  };
  // A launch is the designator's year and number ("2019-074" of "2019-074A").
  auto launch_of = [&](const CsvRow& row) { return std::string(field(row, designator_col).substr(0, 8)); };
  std::vector<LaunchRecord> out;
  std::vector<std::pair<std::size_t, std::string>> decayed;  // index in out, launch
  std::unordered_map<std::string, double> launch_inclination_deg;
  for (const CsvRow& row : table.rows) {
    if (row.fields.size() <= std::max({col[0], col[1], col[2]})) continue;
    const std::string type = text::upper(text::trim(row.fields[col[1]]));
    if (type != "PAYLOAD" && type != "ROCKET BODY") continue;
    const std::string_view id_text = text::trim(row.fields[col[0]]);
    ObjectId id = 0;
    if (std::from_chars(id_text.data(), id_text.data() + id_text.size(), id).ec != std::errc{}) continue;
    const auto launch = UtcEpoch::parse_iso8601(std::string(text::trim(row.fields[col[2]])) + "T00:00:00Z");
    if (!launch) continue;
    LaunchRecord r;
    r.id = id;
    r.launch = *launch;
    r.type = type == "PAYLOAD" ? ObjectType::kPayload : ObjectType::kRocketBody;
    const auto set = by_id.find(id);
    if (set == by_id.end()) {
      const std::string_view decay_text = field(row, decay_col);
      const auto decay = UtcEpoch::parse_iso8601(std::string(decay_text.substr(0, 10)) + "T00:00:00Z");
      if (decay_text.size() < 10 || !decay || !(decay->seconds_since(*launch) > 0.0)) continue;
      r.lived_years = decay->seconds_since(*launch) / kYear_s;
      decayed.emplace_back(out.size(), launch_of(row));
      out.push_back(r);
      continue;
    }
    const MeanElements& el = *set->second;
    // SGP4's convention: a from the Kozai mean motion [rad/min] in Earth radii.
    const double a_km = std::pow(sgp4::kXke / el.mean_motion_rad_min, 2.0 / 3.0) * sgp4::kEarthRadius_km;
    r.perigee_km = a_km * (1.0 - el.eccentricity) - sgp4::kEarthRadius_km;
    r.apogee_km = a_km * (1.0 + el.eccentricity) - sgp4::kEarthRadius_km;
    r.inclination_deg = el.inclination_rad * 180.0 / std::numbers::pi;
    // The launch's plane for its decayed objects: its first object in LEO (a GTO launch's payloads in
    // GEO are not its rocket body's plane).
    if (designator_col && r.perigee_km < 2000.0)
      launch_inclination_deg.emplace(launch_of(row), r.inclination_deg);
    out.push_back(r);
  }
  // Decayed objects take their launch's plane; those of launches with no object left are dropped.
  std::vector<bool> drop(out.size(), false);
  for (const auto& [index, launch] : decayed) {
    const auto it = launch_inclination_deg.find(launch);
    if (launch.size() == 8 && it != launch_inclination_deg.end())
      out[index].inclination_deg = it->second;
    else
      drop[index] = true;
  }
  std::vector<LaunchRecord> kept;
  kept.reserve(out.size());
  for (std::size_t i = 0; i < out.size(); ++i)
    if (!drop[i]) kept.push_back(out[i]);
  return kept;
}

double altitude_for_lifetime_km(double lived_years, double inclination_deg, ObjectType type) {
  constexpr double kBurnUp_m = 150.0e3, kFloor_km = 160.0, kCeiling_m = 2000.0e3, kDragCoefficient = 2.2;
  const bool payload = type == ObjectType::kPayload;
  const double cda =
      drag_area_to_mass_from_size(payload ? kPayloadRadius_m : kRocketBodyRadius_m,
                                  payload ? kPayloadMass_kg : kRocketBodyMass_kg, kDragCoefficient);
  const double altitude_m = disposal_altitude_m(lived_years, inclination_deg * std::numbers::pi / 180.0, cda,
                                                kBurnUp_m, kCeiling_m, DensityTable::standard());
  return std::max(kFloor_km, altitude_m * 1e-3);
}

LaunchPlan business_as_usual_plan(const std::vector<LaunchRecord>& records, const UtcEpoch& window_end,
                                  double window_years, const UtcEpoch& until) {
  const double cycle_s = window_years * kYear_s;
  const double span_s = until.seconds_since(window_end);
  LaunchPlan plan;
  for (const LaunchRecord& rec : records) {
    const double age_s = window_end.seconds_since(rec.launch);
    if (!(age_s > 0.0 && age_s <= cycle_s)) continue;
    const bool decayed = rec.lived_years > 0.0;  // its orbit is the one given below
    if (!decayed && (rec.perigee_km < 100.0 || rec.perigee_km >= 2000.0 || rec.apogee_km < rec.perigee_km ||
                     rec.apogee_km > 40000.0))
      continue;
    const double decayed_altitude_km =
        decayed ? altitude_for_lifetime_km(rec.lived_years, rec.inclination_deg, rec.type) : 0.0;
    // Relaunched at launch + k cycles, k >= 1, while before `until`.
    for (double t = cycle_s - age_s; t < span_s; t += cycle_s) {
      LaunchRow r;
      r.epoch = window_end.plus_seconds(t);
      r.perigee_km = rec.perigee_km;
      r.apogee_km = rec.apogee_km;
      r.inclination_deg = rec.inclination_deg;
      r.type = rec.type;
      const bool payload = r.type == ObjectType::kPayload;
      r.mass_kg = payload ? kPayloadMass_kg : kRocketBodyMass_kg;
      r.radius_m = payload ? kPayloadRadius_m : kRocketBodyRadius_m;
      r.manoeuvres = payload;
      if (decayed) {  // it did not last: passive, on an orbit that decays as it did
        r.perigee_km = r.apogee_km = decayed_altitude_km;
        r.lifetime_years = 0.0;
        r.manoeuvres = false;
      }
      r.label = "business as usual: " + std::to_string(rec.id);
      plan.rows.push_back(r);
    }
  }
  return plan;
}

}  // namespace kessler
