// The short name of a scenario enum value, as scenario files write it: PROPAGATOR_SGP4 -> sgp4, given
// the type's prefix PROPAGATOR_ (from its name, Propagator). Shared by the parser and the validation.
#pragma once

#include <google/protobuf/descriptor.h>

#include <cctype>
#include <string>

namespace kessler {

inline std::string short_enum_name(const google::protobuf::EnumValueDescriptor* value) {
  std::string prefix;
  for (char c : value->type()->name()) {
    if (std::isupper(static_cast<unsigned char>(c)) && !prefix.empty()) prefix += '_';
    prefix += static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  }
  prefix += '_';
  std::string name = value->name();
  if (name.rfind(prefix, 0) == 0) name = name.substr(prefix.size());
  for (auto& c : name) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return name;
}

// The short names of the type's values but the unspecified one (number 0), comma-separated.
inline std::string short_enum_choices(const google::protobuf::EnumDescriptor* type) {
  std::string choices;
  for (int i = 0; i < type->value_count(); ++i)
    if (type->value(i)->number() != 0)
      choices += (choices.empty() ? "" : ", ") + short_enum_name(type->value(i));
  return choices;
}

}  // namespace kessler
