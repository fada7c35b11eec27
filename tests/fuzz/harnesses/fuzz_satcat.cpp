// SATCAT CSV and active lists (core/catalog/satcat.hpp).
#include <cstddef>
#include <cstdint>
#include <string_view>
#include <vector>

#include "core/catalog/satcat.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  (void)kessler::parse_satcat_csv(text, "fuzz");
  std::vector<kessler::ParseProblem> problems;
  (void)kessler::parse_active_list(text, "fuzz", &problems);
  return 0;
}
