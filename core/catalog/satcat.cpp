#include "core/catalog/satcat.hpp"

#include <zlib.h>

#include "core/catalog/csv.hpp"
#include "core/catalog/omm.hpp"
#include "core/catalog/text_fields.hpp"
#include "core/catalog/tle.hpp"

namespace kessler {
namespace {

std::string normalise_object_type(std::string_view raw) {
  std::string t = text::upper(text::trim(raw));
  if (t == "PAY" || t == "PAYLOAD") return "PAYLOAD";
  if (t == "R/B" || t == "ROCKET BODY") return "ROCKET BODY";
  if (t == "DEB" || t == "DEBRIS") return "DEBRIS";
  if (t == "UNK" || t == "UNKNOWN" || t.empty()) return "UNKNOWN";
  return t;
}

}  // namespace

const char* rcs_size_class_name(RcsSizeClass c) {
  switch (c) {
    case RcsSizeClass::kSmall:
      return "small";
    case RcsSizeClass::kMedium:
      return "medium";
    case RcsSizeClass::kLarge:
      return "large";
    default:
      return "unknown";
  }
}

RcsSizeClass rcs_size_class_of(double rcs_m2) {
  if (rcs_m2 < 0.1) return RcsSizeClass::kSmall;
  if (rcs_m2 <= 1.0) return RcsSizeClass::kMedium;
  return RcsSizeClass::kLarge;
}

bool is_active_status_code(char code) {
  return code == '+' || code == 'P' || code == 'B' || code == 'S' || code == 'X';
}

SatcatTable parse_satcat_csv(std::string_view text, const std::string& source) {
  SatcatTable out;
  const CsvTable table = parse_csv(text);
  const auto id_col = table.column("NORAD_CAT_ID");
  if (!id_col) {
    out.problems.push_back({source, 1, "header", "SATCAT header has no NORAD_CAT_ID column"});
    return out;
  }
  const auto type_col = table.column("OBJECT_TYPE");
  const auto size_col = table.column("RCS_SIZE");
  const auto status_col = table.column("OPS_STATUS_CODE");
  auto rcs_col = table.column("RCS");
  if (!rcs_col) rcs_col = table.column("RCSVALUE");
  auto designator_col = table.column("INTLDES");
  if (!designator_col) designator_col = table.column("OBJECT_ID");
  auto decay_col = table.column("DECAY");
  const auto debut_col = table.column("DEBUT");
  if (!decay_col) decay_col = table.column("DECAY_DATE");
  auto name_col = table.column("OBJECT_NAME");
  if (!name_col) name_col = table.column("SATNAME");
  out.flavour = status_col ? "celestrak" : "space-track";

  for (const CsvRow& row : table.rows) {
    ++out.rows;
    auto field = [&](const std::optional<std::size_t>& col) -> std::string_view {
      return col && *col < row.fields.size() ? text::trim(row.fields[*col]) : std::string_view{};
    };
    SatcatEntry e;
    long long id = 0;
    std::string why;
    if (!text::parse_int(field(id_col), id, &why) || id < 0) {
      out.problems.push_back({source, row.line, "number", "NORAD_CAT_ID: " + why});
      continue;
    }
    e.id = static_cast<ObjectId>(id);
    e.name = std::string(field(name_col));
    e.object_type = normalise_object_type(field(type_col));
    const std::string size = text::upper(field(size_col));
    if (size == "SMALL") e.size_class = RcsSizeClass::kSmall;
    if (size == "MEDIUM") e.size_class = RcsSizeClass::kMedium;
    if (size == "LARGE") e.size_class = RcsSizeClass::kLarge;
    const std::string_view rcs_text = field(rcs_col);
    if (!rcs_text.empty()) {
      double rcs = 0.0;
      if (!text::parse_double(rcs_text, rcs, &why)) {
        out.problems.push_back({source, row.line, "number", "RCS: " + why});
      } else if (rcs > 0.0) {
        e.rcs_m2 = rcs;
        if (e.size_class == RcsSizeClass::kUnknown) e.size_class = rcs_size_class_of(rcs);
      }
    }
    const std::string_view status = field(status_col);
    if (!status.empty()) e.ops_status_code = status.front();
    e.international_designator = std::string(field(designator_col));
    // Dates ("2019-04-03"), as both flavours write them; a time part is allowed.
    auto date = [&](const std::optional<std::size_t>& col, const char* name) -> std::optional<UtcEpoch> {
      const std::string_view text = field(col);
      if (text.empty()) return std::nullopt;
      if (auto when = UtcEpoch::parse_iso8601(std::string(text.substr(0, 10)) + "T00:00:00Z", &why))
        return when;
      out.problems.push_back({source, row.line, "date", std::string(name) + ": " + why});
      return std::nullopt;
    };
    e.decay = date(decay_col, "DECAY");
    e.debut = date(debut_col, "DEBUT");
    out.entries[e.id] = std::move(e);
  }
  return out;
}

std::unordered_set<ObjectId> parse_active_list(std::string_view text, const std::string& source,
                                               std::vector<ParseProblem>* problems) {
  std::unordered_set<ObjectId> ids;
  const std::string_view head = text::trim(text.substr(0, 4096));
  ElementSetText parsed;
  if (!head.empty() && (head.front() == '[' || head.front() == '{')) {
    parsed = parse_omm_json(text, source);
  } else if (!head.empty() && head.front() == '<') {
    parsed = parse_omm_xml(text, source);
  } else if (head.find("CCSDS_OMM_VERS") != std::string_view::npos) {
    parsed = parse_omm_kvn(text, source);
  } else if (text::upper(head.substr(0, head.find('\n'))).find("NORAD_CAT_ID") != std::string::npos) {
    // Any CSV with a NORAD_CAT_ID column will do: only the ids matter here.
    const CsvTable table = parse_csv(text);
    const auto col = table.column("NORAD_CAT_ID");
    for (const CsvRow& row : table.rows) {
      long long id = 0;
      std::string why;
      if (col && *col < row.fields.size() && text::parse_int(row.fields[*col], id, &why) && id >= 0)
        ids.insert(static_cast<ObjectId>(id));
      else if (problems)
        problems->push_back({source, row.line, "number", "NORAD_CAT_ID: not a catalog number"});
    }
    return ids;
  } else {
    parsed = parse_tle_text(text, {}, source);
  }
  for (const auto& set : parsed.sets) ids.insert(set.elements.catalog_number);
  if (problems) problems->insert(problems->end(), parsed.problems.begin(), parsed.problems.end());
  return ids;
}

std::optional<std::string> read_catalog_file(const std::string& path, std::string* error) {
  // gzopen reads plain files unchanged, so one path serves both.
  gzFile file = gzopen(path.c_str(), "rb");
  if (!file) {
    if (error) *error = "cannot open " + path;
    return std::nullopt;
  }
  std::string out;
  char buffer[1 << 16];
  int n = 0;
  while ((n = gzread(file, buffer, sizeof buffer)) > 0) out.append(buffer, static_cast<std::size_t>(n));
  int code = 0;
  const char* message = gzerror(file, &code);
  const bool failed = n < 0 || (code != Z_OK && code != Z_STREAM_END);
  const std::string why = failed ? std::string(message) : std::string();
  gzclose(file);
  if (failed) {
    if (error) *error = "cannot read " + path + ": " + why;
    return std::nullopt;
  }
  return out;
}

ObjectType object_type_from_satcat(const std::string& t) {
  if (t == "PAYLOAD") return ObjectType::kPayload;
  if (t == "ROCKET BODY") return ObjectType::kRocketBody;
  if (t == "DEBRIS") return ObjectType::kDebris;
  return ObjectType::kUnknown;
}

}  // namespace kessler
