// State-vector tables (core/catalog/state_table.hpp), lenient and strict.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "core/catalog/state_table.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  static const kessler::UtcEpoch epoch = *kessler::UtcEpoch::parse_iso8601("2022-01-22T00:00:00Z");
  kessler::IngestRules rules;
  rules.strict = size % 2 == 1;
  (void)kessler::read_state_table(text, rules, epoch);
  return 0;
}
