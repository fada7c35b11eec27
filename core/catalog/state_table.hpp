// A state-vector table: one object per CSV row,
//   id, epoch, x, y, z [m], vx, vy, vz [m/s], radius [m], mass [kg] or empty, bstar [1/ER] or empty
// (TEME; an optional 12th column status: active/passive or 1/0; an optional header row whose first
// field is not a number). States are taken as they are, so every epoch must be the start epoch (within
// 1 ms). An empty mass follows the mass law from the radius; an empty or non-positive bstar gives
// Cd A/m from Cd = 2.2 and the size. Bad rows are rejected with line and reason (strict: refused).
#pragma once

#include <string>
#include <string_view>

#include "core/catalog/ingest.hpp"

namespace kessler {

IngestResult read_state_table(std::string_view text, const IngestRules& rules, const UtcEpoch& start_epoch,
                              const std::string& source = "state table");

}  // namespace kessler
