// kessler watch RUN: follows a run live (a finished one is replayed from the store).
#include <memory>

#include "client/command.hpp"
#include "client/commands/follow.hpp"
#include "client/remote/remote_client.hpp"

namespace kessler::cli {

CommandRun setup_watch(CLI::App& command, GlobalOptions& global) {
  struct Options {
    std::int64_t run_id = 0;
    WatchOptions follow;
  };
  auto o = std::make_shared<Options>();
  add_run_id(command, o->run_id);
  command
      .add_option("--after", o->follow.after_seq,
                  "only events after sequence number SEQ (resume where you left off)")
      ->option_text("SEQ");
  add_watch_options(command, o->follow);
  add_global_options(command, global, kWatchOutputHelp);
  command.footer(
      "Follows a run live: its ingest report, a progress bar (simulated time, rate, time left, counts) and "
      "its "
      "events as they come, then its summary. A finished run is replayed from the store. Exit 0 when the run "
      "succeeded, 1 otherwise."
      "\n\n"
      "example:\n  kessler watch 3 --events all");
  return [o, &global] {
    OutputFormat format;
    if (!resolve_output("watch", global.output, {"table", "json"}, format)) return kExitUsage;
    RemoteClient client(server_address(global.server));
    return follow_run(client, o->run_id, o->follow, format);
  };
}

}  // namespace kessler::cli
