// TLE and 3LE text (core/catalog/tle.hpp), with and without checksums.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "core/catalog/tle.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  kessler::TleReadOptions options;
  options.verify_checksums = size % 2 == 0;
  (void)kessler::parse_tle_text(text, options, "fuzz");
  return 0;
}
