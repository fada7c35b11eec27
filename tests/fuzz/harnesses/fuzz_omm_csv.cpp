// OMM CSV text (core/catalog/omm.hpp).
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "core/catalog/omm.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  (void)kessler::parse_omm_csv(text, "fuzz");
  return 0;
}
