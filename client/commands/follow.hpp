// Following a run to its end, for `submit --watch` and `watch`: the ingest report when the run's
// population is known, a progress line (redrawn in place on a terminal), events as they come, then the
// run's summary.
#pragma once

#include <cstdint>
#include <string>

#include "client/command.hpp"
#include "client/remote/remote_client.hpp"

namespace kessler::cli {

struct WatchOptions {
  std::string events;  // all, notable or none; empty: notable, none with json
  double retry_s = 60.0;
  std::uint64_t after_seq = 0;
};

// --events and --retry-s.
void add_watch_options(CLI::App& command, WatchOptions& options);
extern const char* const kWatchOutputHelp;

// Exit 0 when the run succeeded, 1 otherwise (also when the daemon stays away longer than retry_s).
int follow_run(RemoteClient& client, std::int64_t run_id, const WatchOptions& options, OutputFormat format);

}  // namespace kessler::cli
