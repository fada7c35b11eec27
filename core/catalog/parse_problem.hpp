// A record a catalog reader could not accept: where it was and why, with a short reason key for the
// ingest report's counts by reason.
#pragma once

#include <cstddef>
#include <string>

namespace kessler {

struct ParseProblem {
  std::string source;      // file name or a label such as "active list"
  std::size_t line = 0;    // 1-based line number of the record's first line (0 when not line-based)
  std::string reason_key;  // short class of the problem: "checksum", "truncated", "number", ...
  std::string message;     // full text naming the field and the reason
};

}  // namespace kessler
