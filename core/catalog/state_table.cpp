#include "core/catalog/state_table.hpp"

#include <cmath>
#include <unordered_set>

#include "core/catalog/csv.hpp"
#include "core/catalog/text_fields.hpp"

namespace kessler {

IngestResult read_state_table(std::string_view text, const IngestRules& rules, const UtcEpoch& start_epoch,
                              const std::string& source) {
  IngestResult result;
  IngestReport& report = result.report;
  report.source = source;
  report.format = "state table";
  report.start_epoch = start_epoch;
  CsvTable table = parse_csv(text, false);
  std::unordered_set<ObjectId> seen;
  static const char* kNames[] = {"id", "epoch", "x",      "y",    "z",     "vx",
                                 "vy", "vz",    "radius", "mass", "bstar", "status"};

  for (std::size_t r = 0; r < table.rows.size(); ++r) {
    const CsvRow& row = table.rows[r];
    auto reject = [&](const char* key, const std::string& message) {
      report.rejections.push_back({source, row.line, key, message});
    };
    long long id_value = 0;
    std::string why;
    if (r == 0 && !text::parse_int(row.fields[0], id_value, &why)) continue;  // header row
    ++report.records;
    if (row.fields.size() != 11 && row.fields.size() != 12) {
      reject("columns", std::to_string(row.fields.size()) +
                            " fields, expected 11 (id, epoch, x, y, z, vx, vy, vz, "
                            "radius, mass, bstar) or 12 (with status)");
      continue;
    }
    if (!text::parse_int(row.fields[0], id_value, &why) || id_value < 0) {
      reject("number", "id: " + why);
      continue;
    }
    const ObjectId id = static_cast<ObjectId>(id_value);
    const std::string id_text = "object " + std::to_string(id) + ": ";
    auto epoch = UtcEpoch::parse_iso8601(text::trim(row.fields[1]), &why);
    if (!epoch) {
      reject("epoch", id_text + "epoch: " + why);
      continue;
    }
    if (std::fabs(epoch->seconds_since(start_epoch)) > 1e-3) {
      reject("epoch", id_text + "epoch " + epoch->to_iso8601(3) + " is not the start epoch " +
                          start_epoch.to_iso8601(3) + " (state tables are not propagated on ingest)");
      continue;
    }
    double v[11] = {};
    bool ok = true;
    for (int c = 2; c <= 10 && ok; ++c) {
      const bool optional = c >= 9;
      if (optional && text::trim(row.fields[c]).empty()) {
        v[c] = NAN;
        continue;
      }
      if (!text::parse_double(row.fields[c], v[c], &why)) {
        reject("number", id_text + kNames[c] + ": " + why);
        ok = false;
      }
    }
    if (!ok) continue;
    ObjectRecord rec;
    rec.id = id;
    rec.name = "OBJECT " + std::to_string(id);
    rec.position_m = {v[2], v[3], v[4]};
    rec.velocity_m_s = {v[5], v[6], v[7]};
    rec.radius_m = v[8];
    if (!(rec.radius_m > 0.0)) {
      reject("range", id_text + "radius must be positive");
      continue;
    }
    rec.mass_kg = std::isnan(v[9]) ? mass_from_radius_kg(rec.radius_m) : v[9];
    const double bstar = v[10];
    rec.drag_area_to_mass_m2_kg =
        !std::isnan(bstar) && bstar > 0.0
            ? drag_area_to_mass_from_bstar(bstar)
            : drag_area_to_mass_from_size(rec.radius_m, rec.mass_kg, rules.drag_coefficient);
    rec.srp_area_to_mass_m2_kg = srp_area_to_mass(rec.radius_m, rec.mass_kg);
    if (row.fields.size() == 12) {
      const std::string s = text::upper(text::trim(row.fields[11]));
      if (s == "ACTIVE" || s == "1")
        rec.status = ObjectStatus::kActive;
      else if (s == "PASSIVE" || s == "0" || s.empty())
        rec.status = ObjectStatus::kPassive;
      else {
        reject("number", id_text + "status: '" + s + "' is not active/passive/1/0");
        continue;
      }
    }
    if (auto problem = validate_record(rec)) {
      reject("range", *problem);
      continue;
    }
    if (!seen.insert(id).second) {
      reject("duplicate", id_text + "appears more than once");
      continue;
    }
    result.population.add(rec);
  }
  report.rejected = report.rejections.size();
  report.accepted = report.records - report.rejected;
  for (const auto& p : report.rejections) ++report.rejected_by_reason[p.reason_key];
  if (rules.strict && !report.rejections.empty()) {
    const auto& p = report.rejections.front();
    result.refused = true;
    result.error = "strict ingest refused " + source + ": " + std::to_string(report.rejected) +
                   " bad row(s); first at line " + std::to_string(p.line) + ": " + p.message;
    result.population = Population();
    return result;
  }
  if (rules.max_objects && result.population.size() > rules.max_objects) {
    report.filtered_by_reason.push_back({"max objects", result.population.size() - rules.max_objects});
    std::vector<char> flags(result.population.size(), 0);
    for (std::size_t i = rules.max_objects; i < flags.size(); ++i) flags[i] = 1;
    result.population.remove_flagged(flags);
  }
  report.kept = result.population.size();
  for (auto s : result.population.status) (s == ObjectStatus::kActive ? report.active : report.passive)++;
  return result;
}

}  // namespace kessler
