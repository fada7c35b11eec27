// A reader for the JSON that OMM services publish: an array of flat objects whose values are strings,
// numbers, booleans or null (nested values are skipped). Enough for CelesTrak's OMM JSON; not a
// general JSON library.
#pragma once

#include <map>
#include <string>
#include <string_view>
#include <vector>

namespace kessler {

struct FlatJsonObject {
  std::size_t line = 0;                       // 1-based line of the opening brace
  std::map<std::string, std::string> values;  // numbers as their text, strings unescaped, null as ""
};

// Parses `[ {...}, ... ]` or a single `{...}`. Returns false with *error ("line N: reason") when the
// text is not such JSON.
bool parse_flat_json(std::string_view text, std::vector<FlatJsonObject>& objects, std::string* error);

}  // namespace kessler
