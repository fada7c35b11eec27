// A scenario as a wire message (SubmitRun's `scenario`): any bytes that decode, validated, and for a
// valid one its core configuration.
#include <cstddef>
#include <cstdint>

#include "core/scenario/run_builder.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  kessler::v1::Scenario scenario;
  if (!scenario.ParseFromArray(data, static_cast<int>(size))) return 0;
  if (kessler::validate_scenario(scenario)) return 0;
  (void)kessler::to_simulation_config(scenario);
  return 0;
}
