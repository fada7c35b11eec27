// kessler resume RUN: a failed or cancelled run queued again, to continue from its last checkpoint.
#include <iostream>
#include <memory>

#include "client/command.hpp"
#include "client/remote/cli_support.hpp"
#include "client/remote/remote_client.hpp"

namespace kessler::cli {

CommandRun setup_resume(CLI::App& command, GlobalOptions& global) {
  auto run_id = std::make_shared<std::int64_t>(0);
  add_run_id(command, *run_id);
  add_global_options(command, global, "table (default) or json");
  command.footer(
      "Queues a failed or cancelled run again. It continues from its last stored checkpoint (from the start "
      "when it has none); the events it had stay, and those it computes again are stored once, so it ends "
      "as it would have without the interruption. For a run whose MPI job lost a rank, or that failed on a "
      "full disk, once the cause is gone. Follow it with 'kessler watch RUN'.");
  return [run_id, &global] {
    OutputFormat format;
    if (!resolve_output("resume", global.output, {"table", "json"}, format)) return kExitUsage;
    RemoteClient client(server_address(global.server));
    v1::Run run;
    CallResult r = client.resume(*run_id, run);
    if (!r.ok) {
      std::cerr << "kessler resume: " << r.describe() << "\n";
      return r.exit_code();
    }
    if (format == OutputFormat::kJson)
      std::cout << JsonObject().add("run_id", *run_id).add("state", v1::run_state_name(run.state())).str()
                << "\n";
    else
      std::cout << "run " << *run_id << " queued again (position " << run.queue_position()
                << "); it continues from its last checkpoint\n";
    return kExitOk;
  };
}

}  // namespace kessler::cli
