#include "core/traffic/business_as_usual.hpp"

#include <charconv>
#include <cmath>
#include <numbers>
#include <unordered_map>

#include "core/catalog/csv.hpp"
#include "core/catalog/text_fields.hpp"
#include "core/sgp4/wgs72.hpp"

namespace kessler {
namespace {

constexpr double kYear_s = 365.25 * 86400.0;

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
  std::vector<LaunchRecord> out;
  for (const CsvRow& row : table.rows) {
    if (row.fields.size() <= std::max({col[0], col[1], col[2]})) continue;
    const std::string type = text::upper(text::trim(row.fields[col[1]]));
    if (type != "PAYLOAD" && type != "ROCKET BODY") continue;
    const std::string_view id_text = text::trim(row.fields[col[0]]);
    ObjectId id = 0;
    if (std::from_chars(id_text.data(), id_text.data() + id_text.size(), id).ec != std::errc{}) continue;
    const auto set = by_id.find(id);
    const auto launch = UtcEpoch::parse_iso8601(std::string(text::trim(row.fields[col[2]])) + "T00:00:00Z");
    if (set == by_id.end() || !launch) continue;
    const MeanElements& el = *set->second;
    // SGP4's convention: a from the Kozai mean motion [rad/min] in Earth radii.
    const double a_km = std::pow(sgp4::kXke / el.mean_motion_rad_min, 2.0 / 3.0) * sgp4::kEarthRadius_km;
    LaunchRecord r;
    r.id = id;
    r.launch = *launch;
    r.type = type == "PAYLOAD" ? ObjectType::kPayload : ObjectType::kRocketBody;
    r.perigee_km = a_km * (1.0 - el.eccentricity) - sgp4::kEarthRadius_km;
    r.apogee_km = a_km * (1.0 + el.eccentricity) - sgp4::kEarthRadius_km;
    r.inclination_deg = el.inclination_rad * 180.0 / std::numbers::pi;
    out.push_back(r);
  }
  return out;
}

LaunchPlan business_as_usual_plan(const std::vector<LaunchRecord>& records, const UtcEpoch& window_end,
                                  double window_years, const UtcEpoch& until) {
  const double cycle_s = window_years * kYear_s;
  const double span_s = until.seconds_since(window_end);
  LaunchPlan plan;
  for (const LaunchRecord& rec : records) {
    const double age_s = window_end.seconds_since(rec.launch);
    if (!(age_s > 0.0 && age_s <= cycle_s)) continue;
    if (rec.perigee_km < 100.0 || rec.perigee_km >= 2000.0 || rec.apogee_km < rec.perigee_km ||
        rec.apogee_km > 40000.0)
      continue;
    // Relaunched at launch + k cycles, k >= 1, while before `until`.
    for (double t = cycle_s - age_s; t < span_s; t += cycle_s) {
      LaunchRow r;
      r.epoch = window_end.plus_seconds(t);
      r.perigee_km = rec.perigee_km;
      r.apogee_km = rec.apogee_km;
      r.inclination_deg = rec.inclination_deg;
      r.type = rec.type;
      const bool payload = r.type == ObjectType::kPayload;
      r.mass_kg = payload ? 260.0 : 1500.0;
      r.radius_m = payload ? 1.5 : 2.0;
      r.manoeuvres = payload;
      r.label = "business as usual: " + std::to_string(rec.id);
      plan.rows.push_back(r);
    }
  }
  return plan;
}

}  // namespace kessler
