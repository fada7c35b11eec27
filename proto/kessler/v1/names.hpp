// Lower-case names of the API's run states, as the CLI prints them, the daemon's messages say them and
// `kessler runs --state` takes them. One table for client and server (both link kessler_proto).
#pragma once

#include "kessler/v1/service.pb.h"

namespace kessler::v1 {

// "queued", "running", "succeeded", "failed", "cancelled", or "unknown".
const char* run_state_name(RunState state);

}  // namespace kessler::v1
