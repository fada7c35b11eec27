// kessler cancel RUN: a queued run at once, a running one at the end of its current step.
#include <iostream>
#include <memory>

#include "client/command.hpp"
#include "client/remote/cli_support.hpp"
#include "client/remote/remote_client.hpp"

namespace kessler::cli {

CommandRun setup_cancel(CLI::App& command, GlobalOptions& global) {
  auto run_id = std::make_shared<std::int64_t>(0);
  add_run_id(command, *run_id);
  add_global_options(command, global, "table (default) or json");
  command.footer(
      "Cancels a run: a queued run at once, a running one at the end of its current step. Its events so far "
      "stay queryable.");
  return [run_id, &global] {
    OutputFormat format;
    if (!resolve_output("cancel", global.output, {"table", "json"}, format)) return kExitUsage;
    RemoteClient client(server_address(global.server));
    v1::Run run;
    CallResult r = client.cancel(*run_id, run);
    if (!r.ok) {
      std::cerr << "kessler cancel: " << r.describe() << "\n";
      return r.exit_code();
    }
    if (format == OutputFormat::kJson)
      std::cout << JsonObject().add("run_id", *run_id).add("state", v1::run_state_name(run.state())).str()
                << "\n";
    else if (run.state() == v1::RUN_STATE_CANCELLED)
      std::cout << "run " << *run_id << " cancelled\n";
    else
      std::cout << "run " << *run_id << " cancelling at the end of its current step\n";
    return kExitOk;
  };
}

}  // namespace kessler::cli
