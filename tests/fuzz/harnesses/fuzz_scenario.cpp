// Scenario text, YAML or JSON (core/scenario/run_builder.hpp): parsed, validated, and for a valid one
// its core configuration, as SubmitRun and kessler run do before anything runs.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "core/scenario/run_builder.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  kessler::v1::Scenario scenario;
  if (kessler::parse_scenario(text, scenario)) return 0;
  if (kessler::validate_scenario(scenario)) return 0;
  (void)kessler::to_simulation_config(scenario);
  return 0;
}
