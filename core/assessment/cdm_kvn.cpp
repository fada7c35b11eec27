// CDM in KVN: reading keyword = value [unit] lines into sections, and writing them back.
#include <algorithm>
#include <cstdio>

#include "core/assessment/cdm.hpp"

namespace kessler::assessment {

const CdmField* Cdm::find(const std::vector<CdmField>& section, std::string_view keyword) {
  for (const CdmField& f : section)
    if (f.keyword == keyword) return &f;
  return nullptr;
}

CdmError cdm_error(std::size_t line, std::string_view keyword, std::string_view message) {
  std::string text = "line " + std::to_string(line);
  if (!keyword.empty()) text += ", keyword " + std::string(keyword);
  text += ": ";
  text += message;
  return {line, std::string(keyword), std::move(text)};
}

namespace {

std::string_view trim(std::string_view s) {
  const auto first = s.find_first_not_of(" \t\r\n");
  if (first == std::string_view::npos) return {};
  const auto last = s.find_last_not_of(" \t\r\n");
  return s.substr(first, last - first + 1);
}

// U+2212 MINUS SIGN (as in the standard's own annex example) read as '-'.
std::string normalise(std::string_view s) {
  std::string out(s);
  for (std::size_t at = out.find("\xE2\x88\x92"); at != std::string::npos; at = out.find("\xE2\x88\x92", at))
    out.replace(at, 3, "-");
  return out;
}

bool is_header_keyword(std::string_view k) {
  return k == "CCSDS_CDM_VERS" || k == "CREATION_DATE" || k == "ORIGINATOR" || k == "MESSAGE_FOR" ||
         k == "MESSAGE_ID";
}

bool valid_keyword(std::string_view k) {
  return !k.empty() && std::all_of(k.begin(), k.end(), [](char c) {
    return (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_';
  });
}

// Where the fields go while reading: the header, the relative data, then an object's section.
struct SectionCursor {
  Cdm& cdm;
  int section = 0;  // 0 header, 1 relative, 2 object 1, 3 object 2
  std::vector<CdmField>& current() {
    if (section == 0) return cdm.header;
    if (section == 1) return cdm.relative;
    return cdm.objects[static_cast<std::size_t>(section - 2)];
  }
};

bool place_field(SectionCursor& cursor, CdmField field, std::vector<CdmError>& errors) {
  if (field.keyword == "OBJECT") {
    if (field.value != "OBJECT1" && field.value != "OBJECT2") {
      errors.push_back(
          cdm_error(field.line, "OBJECT", "must be OBJECT1 or OBJECT2, got '" + field.value + "'"));
      return false;
    }
    const int section = field.value == "OBJECT1" ? 2 : 3;
    if (section <= cursor.section || !cursor.cdm.objects[static_cast<std::size_t>(section - 2)].empty()) {
      errors.push_back(cdm_error(field.line, "OBJECT", field.value + " out of order or repeated"));
      return false;
    }
    cursor.section = section;
  } else if (field.keyword != "COMMENT" && cursor.section == 0 && !is_header_keyword(field.keyword)) {
    cursor.section = 1;
  } else if (cursor.section >= 1 && is_header_keyword(field.keyword)) {
    errors.push_back(cdm_error(field.line, field.keyword, "header keyword after the header"));
    return false;
  }
  cursor.current().push_back(std::move(field));
  return true;
}

bool parse_kvn_line(std::string_view line, std::size_t number, CdmField& field,
                    std::vector<CdmError>& errors) {
  field.line = number;
  if (line.starts_with("COMMENT") && (line.size() == 7 || line[7] == ' ' || line[7] == '\t')) {
    field.keyword = "COMMENT";
    field.value = normalise(trim(line.substr(7)));
    return true;
  }
  const auto equals = line.find('=');
  if (equals == std::string_view::npos) {
    errors.push_back(
        cdm_error(number, "", "expected KEYWORD = value, got '" + std::string(line.substr(0, 60)) + "'"));
    return false;
  }
  field.keyword = std::string(trim(line.substr(0, equals)));
  if (!valid_keyword(field.keyword)) {
    errors.push_back(cdm_error(number, "", "not a keyword: '" + field.keyword.substr(0, 60) + "'"));
    return false;
  }
  std::string_view value = trim(line.substr(equals + 1));
  if (value.ends_with(']')) {
    const auto open = value.rfind('[');
    if (open != std::string_view::npos) {
      field.unit = std::string(trim(value.substr(open + 1, value.size() - open - 2)));
      value = trim(value.substr(0, open));
    }
  }
  field.value = normalise(value);
  return true;
}

}  // namespace

bool read_cdm_kvn(std::string_view text, Cdm& out, std::vector<CdmError>& errors) {
  out = Cdm{};
  if (text.size() > kMaxCdmBytes) {
    errors.push_back(cdm_error(0, "",
                               "message of " + std::to_string(text.size()) + " bytes, over the limit of " +
                                   std::to_string(kMaxCdmBytes)));
    return false;
  }
  if (text.starts_with("\xEF\xBB\xBF")) text.remove_prefix(3);  // UTF-8 byte-order mark
  SectionCursor cursor{out};
  const std::size_t errors_before = errors.size();
  // Comments belong to the section of the keyword after them (a section's opening comments).
  std::vector<CdmField> comments;
  std::size_t number = 0;
  while (!text.empty() && errors.size() - errors_before < 20) {  // 20 problems tell enough
    const auto end = text.find('\n');
    const std::string_view raw = text.substr(0, end);
    text.remove_prefix(end == std::string_view::npos ? text.size() : end + 1);
    ++number;
    const std::string_view line = trim(raw);
    if (line.empty()) continue;
    CdmField field;
    if (!parse_kvn_line(line, number, field, errors)) continue;
    if (field.keyword == "COMMENT") {
      comments.push_back(std::move(field));
      continue;
    }
    if (!place_field(cursor, std::move(field), errors)) continue;
    auto& section = cursor.current();
    section.insert(section.end() - 1, std::make_move_iterator(comments.begin()),
                   std::make_move_iterator(comments.end()));
    comments.clear();
  }
  auto& last = cursor.current();
  last.insert(last.end(), comments.begin(), comments.end());
  if (out.header.empty() && out.relative.empty())
    errors.push_back(cdm_error(number, "", "no CDM keywords found"));
  return errors.size() == errors_before;
}

namespace {

void write_kvn_fields(const std::vector<CdmField>& fields, std::string& out) {
  char buffer[96];
  for (const CdmField& f : fields) {
    if (f.keyword == "COMMENT") {
      out += "COMMENT " + f.value + "\n";
      continue;
    }
    std::snprintf(buffer, sizeof buffer, "%-36s = ", f.keyword.c_str());
    out += buffer;
    out += f.value;
    if (!f.unit.empty()) {
      if (f.value.size() < 30) out.append(30 - f.value.size(), ' ');
      out += " [" + f.unit + "]";
    }
    out += '\n';
  }
}

}  // namespace

std::string write_cdm_kvn(const Cdm& cdm) {
  std::string out;
  out.reserve(8192);
  write_kvn_fields(cdm.header, out);
  write_kvn_fields(cdm.relative, out);
  write_kvn_fields(cdm.objects[0], out);
  write_kvn_fields(cdm.objects[1], out);
  return out;
}

bool read_cdm(std::string_view text, Cdm& out, std::vector<CdmError>& errors) {
  std::string_view body = text;
  if (body.starts_with("\xEF\xBB\xBF")) body.remove_prefix(3);
  const auto first = body.find_first_not_of(" \t\r\n");
  if (first != std::string_view::npos && body[first] == '<') return read_cdm_xml(text, out, errors);
  return read_cdm_kvn(text, out, errors);
}

}  // namespace kessler::assessment
