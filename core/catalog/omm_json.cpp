// OMM JSON (CelesTrak's and Space-Track's form): an array of flat objects, or one object. simdjson's
// On-Demand reader: validating, fast on whole catalogs and it hands numbers over as their text, so the
// element values go through the same parsing as every other format.
#include <simdjson.h>

#include <map>
#include <string>

#include "core/catalog/omm.hpp"
#include "core/catalog/text_fields.hpp"

namespace kessler {
namespace {

namespace od = simdjson::ondemand;

// What went wrong, and where: the record (1-based) and field being read when simdjson refused.
struct JsonFailure {
  std::size_t record = 0;
  std::string field;
  const char* at = nullptr;  // the start of the record or field value being read
};

// A scalar as the other formats see it: strings unescaped, numbers and booleans as their text, null
// empty. Nested arrays and objects carry no OMM field: empty, and skipped.
simdjson::error_code field_text(od::value value, std::string& out) {
  od::json_type type;
  if (auto error = value.type().get(type)) return error;
  switch (type) {
    case od::json_type::string: {
      std::string_view s;
      if (auto error = value.get_string().get(s)) return error;
      out.assign(s);
      return simdjson::SUCCESS;
    }
    case od::json_type::number:  // its text: the element parser checks it as in the other formats
      out.assign(text::trim(value.raw_json_token()));
      return simdjson::SUCCESS;
    case od::json_type::boolean: {
      bool b = false;
      if (auto error = value.get_bool().get(b)) return error;
      out = b ? "true" : "false";
      return simdjson::SUCCESS;
    }
    case od::json_type::null: {
      bool is_null = false;
      if (auto error = value.is_null().get(is_null)) return error;
      out.clear();
      return is_null ? simdjson::SUCCESS : simdjson::N_ATOM_ERROR;
    }
    default:
      out.clear();
      return simdjson::SUCCESS;  // On-Demand skips the unread value when the object moves on
  }
}

simdjson::error_code read_object(od::value value, std::map<std::string, std::string>& fields,
                                 JsonFailure& failure) {
  od::object object;
  if (auto error = value.get_object().get(object)) return error;
  for (auto field : object) {
    std::string_view key;
    if (auto error = field.unescaped_key().get(key)) return error;
    failure.field = text::upper(key);
    od::value field_value;
    if (auto error = field.value().get(field_value)) return error;
    if (auto error = field_value.current_location().get(failure.at)) return error;
    std::string text;
    if (auto error = field_text(field_value, text)) return error;
    fields[failure.field] = std::move(text);
  }
  failure.field.clear();
  return simdjson::SUCCESS;
}

}  // namespace

ElementSetText parse_omm_json(std::string_view text, const std::string& source) {
  ElementSetText out;
  const simdjson::padded_string padded(text);
  od::parser parser;
  od::document doc;
  text::LineCounter lines(padded.data(), padded.size());
  JsonFailure failure;
  auto offset = [&](const char* at) { return static_cast<std::size_t>(at - padded.data()); };
  std::map<std::string, std::string> fields;

  // Each record goes to `out` as it is read; a JSON error later discards them all.
  auto read_one = [&](od::value value) -> simdjson::error_code {
    ++failure.record;
    if (auto error = value.current_location().get(failure.at)) return error;
    const std::size_t line = lines.line_at(offset(failure.at));
    fields.clear();
    if (auto error = read_object(value, fields, failure)) return error;
    add_omm_fields(out, source, line, fields);
    return simdjson::SUCCESS;
  };
  auto read_document = [&]() -> simdjson::error_code {
    if (auto error = parser.iterate(padded).get(doc)) return error;
    od::json_type type;
    if (auto error = doc.type().get(type)) return error;
    if (type == od::json_type::object) {
      od::value value;
      if (auto error = doc.get_value().get(value)) return error;
      if (auto error = read_one(value)) return error;
    } else {
      od::array array;
      if (auto error = doc.get_array().get(array)) return error;
      for (auto element : array) {
        od::value value;
        if (auto error = element.get(value)) return error;
        if (auto error = read_one(value)) return error;
      }
    }
    // On-Demand stops at the root's end; a token left after it is trailing content.
    const char* rest = nullptr;
    if (doc.current_location().get(rest) != simdjson::SUCCESS) return simdjson::SUCCESS;
    failure.at = rest;
    return simdjson::TRAILING_CONTENT;
  };

  if (const simdjson::error_code error = read_document()) {
    // One bad spot makes the whole text suspect: nothing from it is taken.
    out = ElementSetText{};
    const std::size_t line = failure.at ? lines.line_at(offset(failure.at)) : 0;
    std::string where;
    if (failure.record) where = "record " + std::to_string(failure.record) + ", ";
    if (!failure.field.empty()) where += "field " + failure.field + ", ";
    out.problems.push_back({source, line, "json",
                            "not OMM JSON: " + where + (line ? "line " + std::to_string(line) + ": " : "") +
                                simdjson::error_message(error)});
    return out;
  }
  return out;
}

}  // namespace kessler
