// Scenario text (YAML, or JSON as its subset) onto v1::Scenario by walking the message descriptor, so
// every field of the schema maps without a hand-written table. Keys are the proto field names; enum
// values are given by their short lower-case name ("sgp4") or their full name ("PROPAGATOR_SGP4").
#include <yaml-cpp/yaml.h>

#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <set>
#include <string_view>
#include <vector>

#include "core/scenario/enum_names.hpp"
#include "core/scenario/run_builder.hpp"

namespace kessler {
namespace {

namespace pb = google::protobuf;

std::string join_path(const std::string& path, const std::string& key) {
  return path.empty() ? key : path + "." + key;
}

// Bad input is quoted by a short prefix only: an error message must stay small whatever was sent.
std::string quoted_prefix(const std::string& text) {
  constexpr std::size_t kMaxQuoted = 40;
  if (text.size() <= kMaxQuoted) return text;
  return text.substr(0, kMaxQuoted) + "... (" + std::to_string(text.size()) + " bytes)";
}

std::string describe(const YAML::Node& node) {
  switch (node.Type()) {
    case YAML::NodeType::Map:
      return "a mapping";
    case YAML::NodeType::Sequence:
      return "a list";
    case YAML::NodeType::Null:
      return "nothing";
    case YAML::NodeType::Scalar:
      return (node.Tag() == "!" ? "the string '" : "'") + quoted_prefix(node.Scalar()) + "'";
    default:
      return "an undefined value";
  }
}

// Whether a document marker ('---', or '...' then more) follows content at the top level. A marker is
// a line that starts with it at column 0 (content of a block scalar is indented, so it has none).
// yaml-cpp's LoadAll would tell too, but it loops forever on some malformed texts.
bool holds_a_second_document(std::string_view text) {
  bool content = false, ended = false;
  std::size_t at = 0;
  while (at < text.size()) {
    std::size_t end = text.find('\n', at);
    if (end == std::string_view::npos) end = text.size();
    const std::string_view line = text.substr(at, end - at);
    at = end + 1;
    const bool start_marker =
        line.rfind("---", 0) == 0 && (line.size() == 3 || std::isspace(static_cast<unsigned char>(line[3])));
    const bool end_marker =
        line.rfind("...", 0) == 0 && (line.size() == 3 || std::isspace(static_cast<unsigned char>(line[3])));
    if (start_marker) {
      if (content || ended) return true;
      continue;
    }
    if (end_marker) {
      ended = content;
      continue;
    }
    const std::size_t first = line.find_first_not_of(" \t\r");
    if (first == std::string_view::npos || line[first] == '#') continue;
    if (ended) return true;
    content = true;
  }
  return false;
}

class Mapper {
 public:
  std::optional<FieldError> message(const YAML::Node& node, pb::Message& msg, const std::string& path) {
    if (!node.IsMap()) return FieldError{path, "expected a mapping of keys, got " + describe(node)};
    const pb::Descriptor* desc = msg.GetDescriptor();
    const pb::Reflection* refl = msg.GetReflection();
    std::set<int> seen;  // field numbers: a key given twice (or in both spellings) is refused
    for (const auto& kv : node) {
      if (!kv.first.IsScalar()) return FieldError{path, "a key must be a plain name"};
      const std::string key = kv.first.Scalar();
      const std::string key_path = join_path(path, key);
      const pb::FieldDescriptor* field = desc->FindFieldByName(key);
      // The protobuf JSON mapping's lowerCamelCase names ("durationDays") are accepted too.
      if (!field) field = desc->FindFieldByCamelcaseName(key);
      if (!field) {
        std::string known;
        for (int i = 0; i < desc->field_count(); ++i) known += (i ? ", " : "") + desc->field(i)->name();
        return FieldError{quoted_prefix(key_path), "unknown key (known keys here: " + known + ")"};
      }
      if (!seen.insert(field->number()).second) return FieldError{key_path, "is given twice"};
      if (const pb::OneofDescriptor* oneof = field->real_containing_oneof()) {
        if (const pb::FieldDescriptor* other = refl->GetOneofFieldDescriptor(msg, oneof))
          return FieldError{key_path, "conflicts with '" + other->name() + "': give only one of them"};
      }
      if (kv.second.IsNull()) return FieldError{key_path, "has no value"};
      if (field->is_repeated()) {
        if (!kv.second.IsSequence())
          return FieldError{key_path, "expected a list, got " + describe(kv.second)};
        for (std::size_t i = 0; i < kv.second.size(); ++i) {
          if (auto e = value(kv.second[i], msg, field, key_path + "[" + std::to_string(i) + "]")) return e;
        }
      } else if (auto e = value(kv.second, msg, field, key_path)) {
        return e;
      }
    }
    return std::nullopt;
  }

 private:
  std::optional<FieldError> value(const YAML::Node& node, pb::Message& msg, const pb::FieldDescriptor* field,
                                  const std::string& path) {
    const pb::Reflection* refl = msg.GetReflection();
    const bool rep = field->is_repeated();
    using T = pb::FieldDescriptor;
    if (field->cpp_type() == T::CPPTYPE_MESSAGE) {
      pb::Message* sub = rep ? refl->AddMessage(&msg, field) : refl->MutableMessage(&msg, field);
      return message(node, *sub, path);
    }
    if (!node.IsScalar()) return FieldError{path, "expected " + expected(field) + ", got " + describe(node)};
    const std::string& text = node.Scalar();
    const bool quoted = node.Tag() == "!";
    switch (field->cpp_type()) {
      case T::CPPTYPE_STRING:
        rep ? refl->AddString(&msg, field, text) : refl->SetString(&msg, field, text);
        return std::nullopt;
      case T::CPPTYPE_BOOL: {
        if (quoted || (text != "true" && text != "false"))
          return FieldError{path, "expected true or false, got " + describe(node)};
        rep ? refl->AddBool(&msg, field, text == "true") : refl->SetBool(&msg, field, text == "true");
        return std::nullopt;
      }
      case T::CPPTYPE_DOUBLE:
      case T::CPPTYPE_FLOAT: {
        double v = 0;
        if (quoted || !parse_double(text, v))
          return FieldError{path, "expected a number, got " + describe(node)};
        if (!std::isfinite(v)) return FieldError{path, "must be a finite number"};
        if (field->cpp_type() == T::CPPTYPE_DOUBLE)
          rep ? refl->AddDouble(&msg, field, v) : refl->SetDouble(&msg, field, v);
        else
          rep ? refl->AddFloat(&msg, field, static_cast<float>(v))
              : refl->SetFloat(&msg, field, static_cast<float>(v));
        return std::nullopt;
      }
      case T::CPPTYPE_INT64:
      case T::CPPTYPE_INT32: {
        std::int64_t v = 0;
        auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
        if (!integer_text_ok(field, quoted) || ec == std::errc::invalid_argument ||
            end != text.data() + text.size())
          return FieldError{path, "expected a whole number, got " + describe(node)};
        if (ec == std::errc::result_out_of_range ||
            (field->cpp_type() == T::CPPTYPE_INT32 && (v < INT32_MIN || v > INT32_MAX)))
          return FieldError{path, "is out of range"};
        if (field->cpp_type() == T::CPPTYPE_INT64)
          rep ? refl->AddInt64(&msg, field, v) : refl->SetInt64(&msg, field, v);
        else
          rep ? refl->AddInt32(&msg, field, static_cast<std::int32_t>(v))
              : refl->SetInt32(&msg, field, static_cast<std::int32_t>(v));
        return std::nullopt;
      }
      case T::CPPTYPE_UINT64:
      case T::CPPTYPE_UINT32: {
        if (!text.empty() && text[0] == '-') return FieldError{path, "must not be negative"};
        std::uint64_t v = 0;
        auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
        if (!integer_text_ok(field, quoted) || ec == std::errc::invalid_argument ||
            end != text.data() + text.size())
          return FieldError{path, "expected a whole number, got " + describe(node)};
        if (ec == std::errc::result_out_of_range ||
            (field->cpp_type() == T::CPPTYPE_UINT32 && v > UINT32_MAX))
          return FieldError{path, "is out of range"};
        if (field->cpp_type() == T::CPPTYPE_UINT64)
          rep ? refl->AddUInt64(&msg, field, v) : refl->SetUInt64(&msg, field, v);
        else
          rep ? refl->AddUInt32(&msg, field, static_cast<std::uint32_t>(v))
              : refl->SetUInt32(&msg, field, static_cast<std::uint32_t>(v));
        return std::nullopt;
      }
      case T::CPPTYPE_ENUM: {
        const pb::EnumDescriptor* type = field->enum_type();
        const pb::EnumValueDescriptor* found = nullptr;
        std::string choices;
        for (int i = 0; i < type->value_count(); ++i) {
          const pb::EnumValueDescriptor* v = type->value(i);
          if (v->number() == 0) continue;  // "unspecified" is the absence of the key
          if (text == v->name() || text == short_enum_name(v)) found = v;
          choices += (choices.empty() ? "" : ", ") + short_enum_name(v);
        }
        if (!found)
          return FieldError{path, "unknown value " + describe(node) + " (expected one of: " + choices + ")"};
        rep ? refl->AddEnum(&msg, field, found) : refl->SetEnum(&msg, field, found);
        return std::nullopt;
      }
      default:
        return FieldError{path, "has a type the scenario format does not support"};
    }
  }

  static std::string expected(const pb::FieldDescriptor* field) {
    using T = pb::FieldDescriptor;
    switch (field->cpp_type()) {
      case T::CPPTYPE_STRING:
        return "a string";
      case T::CPPTYPE_BOOL:
        return "true or false";
      case T::CPPTYPE_DOUBLE:
      case T::CPPTYPE_FLOAT:
        return "a number";
      case T::CPPTYPE_ENUM:
        return "a name";
      default:
        return "a whole number";
    }
  }

  // The protobuf JSON mapping writes 64-bit integers as strings; 32-bit ones must be plain numbers.
  static bool integer_text_ok(const pb::FieldDescriptor* field, bool quoted) {
    using T = pb::FieldDescriptor;
    return !quoted || field->cpp_type() == T::CPPTYPE_INT64 || field->cpp_type() == T::CPPTYPE_UINT64;
  }

  static bool parse_double(const std::string& text, double& v) {
    if (text.empty()) return false;
    errno = 0;
    char* end = nullptr;
    v = std::strtod(text.c_str(), &end);
    return end == text.c_str() + text.size() && errno == 0 && text.find_first_of("xXnN") == std::string::npos;
  }
};

}  // namespace

std::optional<FieldError> parse_scenario(std::string_view text, v1::Scenario& out) {
  out.Clear();
  YAML::Node root;
  try {
    if (holds_a_second_document(text))
      return FieldError{"",
                        "the text holds 2 YAML documents (a '---' or '...' line after the first); a "
                        "scenario is one"};
    root = YAML::Load(std::string(text));
  } catch (const YAML::ParserException& e) {
    return FieldError{"", "not valid YAML or JSON: line " + std::to_string(e.mark.line + 1) + ", column " +
                              std::to_string(e.mark.column + 1) + ": " + e.msg};
  }
  if (!root || root.IsNull()) return FieldError{"", "the scenario is empty (it needs at least a population)"};
  try {
    return Mapper().message(root, out, "");
  } catch (const YAML::Exception& e) {
    return FieldError{"", std::string("not valid YAML or JSON: ") + e.what()};
  }
}

}  // namespace kessler
