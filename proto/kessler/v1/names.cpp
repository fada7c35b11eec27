#include "kessler/v1/names.hpp"

namespace kessler::v1 {

const char* run_state_name(RunState state) {
  switch (state) {
    case RUN_STATE_QUEUED:
      return "queued";
    case RUN_STATE_RUNNING:
      return "running";
    case RUN_STATE_SUCCEEDED:
      return "succeeded";
    case RUN_STATE_FAILED:
      return "failed";
    case RUN_STATE_CANCELLED:
      return "cancelled";
    default:
      return "unknown";
  }
}

}  // namespace kessler::v1
