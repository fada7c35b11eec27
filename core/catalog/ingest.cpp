#include "core/catalog/ingest.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <optional>
#include <sstream>
#include <string_view>
#include <unordered_set>

#include "core/catalog/omm.hpp"
#include "core/catalog/satcat.hpp"
#include "core/catalog/text_fields.hpp"
#include "core/integration/burn_up.hpp"
#include "core/sgp4/wgs72.hpp"

namespace kessler {
namespace {

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

std::string format_double(double v, int decimals) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  return buf;
}

// The parsed element sets that are neither too far after the start nor a repeated id; the rest join the
// parse problems as rejections (sorted by line) in the report, with the record counts.
std::vector<ElementSetEntry> screen_sets(ElementSetText& parsed, const std::string& source,
                                         const IngestRules& rules, const UtcEpoch& start_epoch,
                                         IngestReport& report) {
  std::vector<ElementSetEntry> sets;
  sets.reserve(parsed.sets.size());
  std::unordered_set<ObjectId> seen;
  for (auto& entry : parsed.sets) {
    const double after_days = entry.elements.epoch.seconds_since(start_epoch) / 86400.0;
    const std::string id_text = "catalog number " + std::to_string(entry.elements.catalog_number);
    if (after_days > rules.max_epoch_after_start_days) {
      parsed.problems.push_back({source, entry.line, "epoch",
                                 id_text + ": epoch " + entry.elements.epoch.to_iso8601(3) + " is " +
                                     format_double(after_days, 2) + " days after the start epoch (limit " +
                                     format_double(rules.max_epoch_after_start_days, 2) + ")"});
      continue;
    }
    if (!seen.insert(entry.elements.catalog_number).second) {
      parsed.problems.push_back({source, entry.line, "duplicate", id_text + ": appears more than once"});
      continue;
    }
    sets.push_back(std::move(entry));
  }
  std::sort(parsed.problems.begin(), parsed.problems.end(),
            [](const ParseProblem& a, const ParseProblem& b) { return a.line < b.line; });
  report.accepted = sets.size();
  report.rejected = parsed.problems.size();
  report.records = report.accepted + report.rejected;
  for (const auto& p : parsed.problems) ++report.rejected_by_reason[p.reason_key];
  report.rejections = std::move(parsed.problems);
  return sets;
}

// Docked vehicles: the first record of each distinct element set stands for the whole stack; the others
// are flagged.
std::vector<char> docked_flags(const std::vector<ElementSetEntry>& sets, bool drop_docked) {
  const std::size_t n = sets.size();
  std::vector<char> docked(n, 0);
  if (drop_docked) {
    std::map<std::array<double, 8>, std::size_t> first_of_set;
    for (std::size_t i = 0; i < n; ++i) {
      const MeanElements& el = sets[i].elements;
      const std::array<double, 8> key = {el.epoch.jd_whole(),        el.epoch.jd_fraction(),
                                         el.mean_motion_rad_min,     el.eccentricity,
                                         el.inclination_rad,         el.raan_rad,
                                         el.argument_of_perigee_rad, el.mean_anomaly_rad};
      docked[i] = !first_of_set.emplace(key, i).second;
    }
  }
  return docked;
}

// The SATCAT and the active list, where the input has them; their counts and problems go to the report.
struct SideInputs {
  SatcatTable satcat;
  std::unordered_set<ObjectId> active_ids;
};
SideInputs read_side_inputs(const CatalogInput& input, IngestReport& report) {
  SideInputs side;
  if (!input.satcat_csv.empty()) {
    side.satcat = parse_satcat_csv(input.satcat_csv, input.satcat_source);
    report.satcat_rows = side.satcat.rows;
    report.side_input_problems = side.satcat.problems;
  }
  if (!input.active_list.empty()) {
    side.active_ids =
        parse_active_list(input.active_list, input.active_list_source, &report.side_input_problems);
    report.active_list_ids = side.active_ids.size();
  }
  return side;
}

// Every set's SGP4 record and its state at the start epoch (TEME, km and km/s), in parallel.
void propagate_to_start(const std::vector<ElementSetEntry>& sets, const UtcEpoch& start_epoch,
                        std::vector<Sgp4Record>& records, std::vector<Sgp4State>& states) {
  const std::size_t n = sets.size();
#pragma omp parallel for schedule(dynamic, 256)
  for (std::size_t i = 0; i < n; ++i) {
    records[i] = sgp4_initialise(sets[i].elements);
    const double minutes = start_epoch.seconds_since(sets[i].elements.epoch) / 60.0;
    states[i] = records[i].init_error != Sgp4Error::kNone ? Sgp4State{{}, {}, records[i].init_error}
                                                          : sgp4_propagate(records[i], minutes);
  }
}

// The ingest's filter reasons, in the order of the rules (and of the report).
constexpr const char* kFilterReasons[] = {"docked",
                                          "excluded name",
                                          "object type",
                                          "perigee below band",
                                          "apogee above band",
                                          "SGP4 failed",
                                          "decayed before the start",
                                          "radius below minimum",
                                          "invalid state",
                                          "max objects"};

// What the rules of steps 2 and 3 need besides the object.
struct ObjectScreen {
  const IngestRules& rules;
  std::vector<std::string> exclusions;  // names and globs
  std::vector<std::string> types;       // upper-case SATCAT object types; empty: all
  double burn_up_radius2 = 0.0;         // burn_up_radius2 of the burn-up altitude [m^2]
};

// The first rule of steps 2 and 3 an object fails, or nullptr; a_km: its Brouwer mean semi-major axis,
// as SGP4 recovers it [km] (set once the band is checked).
const char* failed_rule(const ObjectScreen& screen, bool docked, const std::string& name,
                        const SatcatEntry* entry, const MeanElements& el, const Sgp4Record& record,
                        const Sgp4State& state, double& a_km) {
  if (docked) return "docked";
  if (std::any_of(screen.exclusions.begin(), screen.exclusions.end(),
                  [&](const std::string& p) { return glob_match(p, name); }))
    return "excluded name";
  if (!screen.types.empty()) {
    const std::string type = entry ? entry->object_type : "UNKNOWN";
    if (std::find(screen.types.begin(), screen.types.end(), type) == screen.types.end()) return "object type";
  }
  a_km = std::pow(sgp4::kXke / record.no_unkozai, 2.0 / 3.0) * sgp4::kEarthRadius_km;
  const double perigee_km = a_km * (1.0 - el.eccentricity) - sgp4::kEarthRadius_km;
  const double apogee_km = a_km * (1.0 + el.eccentricity) - sgp4::kEarthRadius_km;
  if (perigee_km < screen.rules.min_perigee_km) return "perigee below band";
  if (apogee_km > screen.rules.max_apogee_km) return "apogee above band";
  if (state.error != Sgp4Error::kNone) return "SGP4 failed";
  // In metres, as the population will hold it, so that this is the simulation's own burn-up test.
  const auto& r_km = state.position_km;
  if (burns_up(r_km[0] * 1000.0, r_km[1] * 1000.0, r_km[2] * 1000.0, screen.burn_up_radius2))
    return "decayed before the start";
  return nullptr;
}

// An object's record at the start epoch and where its properties came from.
struct KeptObject {
  ObjectRecord record;
  bool sampled = false, bstar_drag = false, by_code = false;
};

// Step 4: position and velocity in m and m/s, radius, mass, drag, SRP and status. nullopt when the
// catalogued RCS gives a radius below the minimum. Sampling without an RCS class is counted in `report`.
std::optional<KeptObject> object_properties(const IngestRules& rules, std::uint64_t seed,
                                            const std::string& name, const MeanElements& el,
                                            const Sgp4State& state, const SatcatEntry* entry,
                                            const std::unordered_set<ObjectId>& active_ids,
                                            IngestReport& report) {
  KeptObject kept;
  ObjectRecord& rec = kept.record;
  rec.id = el.catalog_number;
  rec.name = name;
  for (int k = 0; k < 3; ++k) {
    rec.position_m[k] = state.position_km[k] * 1000.0;
    rec.velocity_m_s[k] = state.velocity_km_s[k] * 1000.0;
  }
  if (entry && entry->rcs_m2) {
    rec.radius_m = radius_from_rcs_m(*entry->rcs_m2);
    if (rec.radius_m < rules.sizes.min_radius_m) return std::nullopt;
  } else {
    const RcsSizeClass c = entry ? entry->size_class : RcsSizeClass::kUnknown;
    rec.radius_m = sample_radius_m(rules.sizes, c, seed, rec.id);
    kept.sampled = true;
    if (c == RcsSizeClass::kUnknown) ++report.radius_sampled_unknown_class;
  }
  rec.mass_kg = mass_from_radius_kg(rec.radius_m);
  kept.bstar_drag = el.bstar_per_earth_radius > 0.0;
  rec.drag_area_to_mass_m2_kg =
      kept.bstar_drag ? drag_area_to_mass_from_bstar(el.bstar_per_earth_radius)
                      : drag_area_to_mass_from_size(rec.radius_m, rec.mass_kg, rules.drag_coefficient);
  rec.srp_area_to_mass_m2_kg = srp_area_to_mass(rec.radius_m, rec.mass_kg);
  kept.by_code = entry && entry->ops_status_code && is_active_status_code(*entry->ops_status_code);
  const bool by_list = active_ids.count(rec.id) > 0;
  rec.status = kept.by_code || by_list ? ObjectStatus::kActive : ObjectStatus::kPassive;
  rec.type = entry ? object_type_from_satcat(entry->object_type) : ObjectType::kUnknown;
  return kept;
}

// The report's counts of where a kept object's properties came from.
void count_kept(const KeptObject& kept, IngestReport& report) {
  ++(kept.sampled ? report.radius_sampled : report.radius_from_rcs);
  ++(kept.bstar_drag ? report.drag_from_bstar : report.drag_from_size);
  if (kept.record.status == ObjectStatus::kActive) {
    ++report.active;
    ++(kept.by_code ? report.active_by_status_code : report.active_by_list);
  } else {
    ++report.passive;
  }
}

// Statistics per status group, for the report.
void summarise_groups(IngestResult& result) {
  IngestReport& report = result.report;
  for (const ObjectStatus status : {ObjectStatus::kActive, ObjectStatus::kPassive}) {
    std::vector<double> radius, mass, sma;
    for (std::size_t i = 0; i < result.population.size(); ++i) {
      if (result.population.status[i] != status) continue;
      radius.push_back(result.population.radius_m[i]);
      mass.push_back(result.population.mass_kg[i]);
      sma.push_back(result.mean_semi_major_axis_km[i]);
    }
    GroupSummary& g = status == ObjectStatus::kActive ? report.active_summary : report.passive_summary;
    g.count = radius.size();
    g.median_radius_m = median(radius);
    g.median_mass_kg = median(mass);
    g.median_semi_major_axis_km = median(sma);
  }
}

}  // namespace

bool glob_match(std::string_view pattern, std::string_view text) {
  auto lower = [](char c) { return static_cast<char>(std::tolower(static_cast<unsigned char>(c))); };
  std::size_t p = 0, t = 0, star = std::string_view::npos, mark = 0;
  while (t < text.size()) {
    if (p < pattern.size() && (pattern[p] == '?' || lower(pattern[p]) == lower(text[t]))) {
      ++p;
      ++t;
    } else if (p < pattern.size() && pattern[p] == '*') {
      star = p++;
      mark = t;
    } else if (star != std::string_view::npos) {
      p = star + 1;
      t = ++mark;
    } else {
      return false;
    }
  }
  while (p < pattern.size() && pattern[p] == '*') ++p;
  return p == pattern.size();
}

CatalogFormat detect_catalog_format(std::string_view text) {
  const std::string_view head = text::trim(text.substr(0, 4096));
  if (head.empty()) return CatalogFormat::kTle;
  if (head.front() == '[' || head.front() == '{') return CatalogFormat::kOmmJson;
  if (head.front() == '<') return CatalogFormat::kOmmXml;
  if (head.find("CCSDS_OMM_VERS") != std::string_view::npos) return CatalogFormat::kOmmKvn;
  const std::string first_line = text::upper(head.substr(0, head.find('\n')));
  if (first_line.find("MEAN_MOTION") != std::string::npos && first_line.find(',') != std::string::npos)
    return CatalogFormat::kOmmCsv;
  return CatalogFormat::kTle;
}

const char* catalog_format_name(CatalogFormat f) {
  switch (f) {
    case CatalogFormat::kTle:
      return "TLE/3LE";
    case CatalogFormat::kOmmCsv:
      return "OMM CSV";
    case CatalogFormat::kOmmJson:
      return "OMM JSON";
    case CatalogFormat::kOmmKvn:
      return "OMM KVN";
    case CatalogFormat::kOmmXml:
      return "OMM XML";
    default:
      return "detect";
  }
}

ElementSetText parse_catalog_text(std::string_view text, CatalogFormat format, const std::string& source,
                                  const TleReadOptions& tle_options) {
  if (format == CatalogFormat::kDetect) format = detect_catalog_format(text);
  switch (format) {
    case CatalogFormat::kOmmCsv:
      return parse_omm_csv(text, source);
    case CatalogFormat::kOmmJson:
      return parse_omm_json(text, source);
    case CatalogFormat::kOmmKvn:
      return parse_omm_kvn(text, source);
    case CatalogFormat::kOmmXml:
      return parse_omm_xml(text, source);
    default:
      return parse_tle_text(text, tle_options, source);
  }
}

std::size_t IngestReport::filtered(const std::string& reason) const {
  for (const auto& [r, n] : filtered_by_reason)
    if (r == reason) return n;
  return 0;
}

std::string IngestReport::text(std::size_t max_listed) const {
  std::ostringstream o;
  o << "Ingest of " << source << " (" << format << ") to " << start_epoch.to_iso8601(3) << "\n";
  o << "  records read:     " << records << "\n";
  o << "  accepted:         " << accepted << "\n";
  o << "  rejected:         " << rejected << "\n";
  for (const auto& [reason, n] : rejected_by_reason) o << "    " << reason << ": " << n << "\n";
  for (std::size_t i = 0; i < rejections.size() && i < max_listed; ++i) {
    const auto& p = rejections[i];
    o << "    " << p.source << ":" << p.line << ": " << p.message << "\n";
  }
  if (rejections.size() > max_listed) o << "    ... " << rejections.size() - max_listed << " more\n";
  o << "  filtered out:\n";
  for (const auto& [reason, n] : filtered_by_reason) o << "    " << reason << ": " << n << "\n";
  for (std::size_t i = 0; i < propagation_failures.size() && i < max_listed; ++i)
    o << "    SGP4 failed for " << propagation_failures[i].first << ": " << propagation_failures[i].second
      << "\n";
  if (propagation_failures.size() > max_listed)
    o << "    ... " << propagation_failures.size() - max_listed << " more SGP4 failures\n";
  o << "  kept:             " << kept << " (active " << active << ", passive " << passive << ")\n";
  o << "  status:           active by SATCAT status code " << active_by_status_code << ", by active list "
    << active_by_list << "\n";
  o << "  radius:           from numeric RCS " << radius_from_rcs << ", sampled by RCS class "
    << radius_sampled << " (of which without a class " << radius_sampled_unknown_class << ")\n";
  o << "  drag:             from BSTAR " << drag_from_bstar << ", from Cd and size " << drag_from_size
    << "\n";
  if (drag_fit) {
    const BallisticFitCounts& f = *drag_fit;
    o << "  drag fitted in " << f.atmosphere << ": from the mean-motion derivative "
      << f.from_mean_motion_derivative << ", from SGP4's BSTAR decay " << f.from_sgp4_bstar
      << ", no decay signal (rule above) " << f.no_signal << "; clamped low " << f.clamped_low << ", high "
      << f.clamped_high << "; stale element sets " << f.stale << "; median fitted / BSTAR rule "
      << format_double(f.median_ratio_to_bstar_mapping, 3) << "\n";
  }
  o << "  SATCAT:           " << satcat_rows << " rows, " << satcat_matched << " matched; active list "
    << active_list_ids << " ids\n";
  if (!side_input_problems.empty()) o << "  side-input problems: " << side_input_problems.size() << "\n";
  for (const auto* g : {&active_summary, &passive_summary}) {
    o << (g == &active_summary ? "  active:  " : "  passive: ") << g->count << " objects, median radius "
      << format_double(g->median_radius_m, 3) << " m, mass " << format_double(g->median_mass_kg, 2)
      << " kg, semi-major axis " << format_double(g->median_semi_major_axis_km, 1) << " km\n";
  }
  return o.str();
}

IngestResult ingest_catalog(const CatalogInput& input, const IngestRules& rules, const UtcEpoch& start_epoch,
                            std::uint64_t seed) {
  IngestResult result;
  IngestReport& report = result.report;
  report.source = input.source;
  report.start_epoch = start_epoch;
  const CatalogFormat format =
      input.format == CatalogFormat::kDetect ? detect_catalog_format(input.text) : input.format;
  report.format = catalog_format_name(format);

  // 1. Parse; reject epochs too far after the start and duplicate ids.
  ElementSetText parsed = parse_catalog_text(input.text, format, input.source, {rules.verify_checksums});
  const std::vector<ElementSetEntry> sets = screen_sets(parsed, input.source, rules, start_epoch, report);
  if (rules.strict && !report.rejections.empty()) {
    const auto& p = report.rejections.front();
    result.refused = true;
    result.error = "strict ingest refused " + input.source + ": " + std::to_string(report.rejected) +
                   " bad record(s); first at line " + std::to_string(p.line) + ": " + p.message;
    return result;
  }

  const SideInputs side = read_side_inputs(input, report);

  // 2. Filters by name, type and mean-element altitude band; 3. SGP4 to the start epoch.
  ObjectScreen screen{rules, rules.exclude_names, {}, burn_up_radius2(rules.burn_up_altitude_km * 1e3)};
  if (rules.default_exclusions)
    for (auto& p : IngestRules::paper_exclusions()) screen.exclusions.push_back(p);
  for (const auto& t : rules.object_types) screen.types.push_back(text::upper(text::trim(t)));

  const std::size_t n = sets.size();
  std::vector<Sgp4Record> records(n);
  std::vector<Sgp4State> states(n);
  propagate_to_start(sets, start_epoch, records, states);

  const std::vector<char> docked = docked_flags(sets, rules.drop_docked);
  std::map<std::string, std::size_t> filtered;
  for (std::size_t i = 0; i < n; ++i) {
    const MeanElements& el = sets[i].elements;
    const ObjectId id = el.catalog_number;
    const auto sat = side.satcat.entries.find(id);
    const SatcatEntry* entry = sat == side.satcat.entries.end() ? nullptr : &sat->second;
    if (entry) ++report.satcat_matched;
    const std::string& name = !el.name.empty() ? el.name : (entry ? entry->name : el.name);

    double a_km = 0.0;
    if (const char* rule = failed_rule(screen, docked[i], name, entry, el, records[i], states[i], a_km)) {
      ++filtered[rule];
      if (std::string_view(rule) == "SGP4 failed")
        report.propagation_failures.push_back({id, sgp4_error_text(states[i].error)});
      continue;
    }
    // 4. Properties.
    const auto kept = object_properties(rules, seed, name, el, states[i], entry, side.active_ids, report);
    if (!kept) {
      ++filtered["radius below minimum"];
      continue;
    }
    if (auto problem = validate_record(kept->record)) {
      ++filtered["invalid state"];
      report.propagation_failures.push_back({id, *problem});
      continue;
    }
    if (rules.max_objects && result.population.size() >= rules.max_objects) {
      ++filtered["max objects"];
      continue;
    }
    count_kept(*kept, report);
    result.population.add(kept->record);
    result.elements.push_back(el);
    result.sgp4_records.push_back(records[i]);
    result.mean_semi_major_axis_km.push_back(a_km);
  }
  for (const char* r : kFilterReasons)
    if (filtered.count(r)) report.filtered_by_reason.push_back({r, filtered[r]});
  report.kept = result.population.size();

  summarise_groups(result);
  return result;
}

}  // namespace kessler
