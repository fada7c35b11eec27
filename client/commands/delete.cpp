// kessler delete RUN: an ended run and everything stored for it.
#include <iostream>
#include <memory>

#include "client/command.hpp"
#include "client/remote/cli_support.hpp"
#include "client/remote/remote_client.hpp"

namespace kessler::cli {

CommandRun setup_delete(CLI::App& command, GlobalOptions& global) {
  auto run_id = std::make_shared<std::int64_t>(0);
  add_run_id(command, *run_id);
  add_global_options(command, global, "table (default) or json");
  command.footer(
      "Deletes an ended run with its events, conjunctions and checkpoints. Cancel a running run first.");
  return [run_id, &global] {
    OutputFormat format;
    if (!resolve_output("delete", global.output, {"table", "json"}, format)) return kExitUsage;
    RemoteClient client(server_address(global.server));
    CallResult r = client.remove(*run_id);
    if (!r.ok) {
      std::cerr << "kessler delete: " << r.describe() << "\n";
      return r.exit_code();
    }
    if (format == OutputFormat::kJson)
      std::cout << JsonObject().add("run_id", *run_id).add("deleted", true).str() << "\n";
    else
      std::cout << "run " << *run_id << " deleted\n";
    return kExitOk;
  };
}

}  // namespace kessler::cli
