// The scenario's `breakups` block: its checks (on the scenario alone, and against the ingested
// population) and its mapping onto the core's BreakupSettings. Used by scenario_validation.cpp and
// run_builder.cpp.
#pragma once

#include <optional>

#include "core/population/population.hpp"
#include "core/scenario/run_builder.hpp"
#include "core/simulation/breakups.hpp"
#include "core/time/epoch.hpp"

namespace kessler {

// Range and consistency checks of scenario.breakups that need no population. `start` is the run's start
// epoch and run_s its simulated length (whole steps), which bound the scheduled epochs.
std::optional<FieldError> validate_breakups(const v1::Scenario& scenario, const UtcEpoch& start,
                                            double run_s);

// Checks of the scheduled events against the population the run starts with: every object exists, and
// collisions whose masses come from the population stay within max_fragments_per_event. Disabled
// breakups are not checked (nothing of them runs).
std::optional<FieldError> check_breakups_against_population(const BreakupSettings& settings,
                                                            const Population& population);

// The core's settings of a valid breakups block; unset fields at their defaults (scenario_defaults.hpp).
BreakupSettings breakup_settings_of(const v1::Breakups& breakups, const UtcEpoch& start);

}  // namespace kessler
