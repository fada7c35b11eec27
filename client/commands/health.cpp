// kessler health: the daemon's standard health check, for scripts, container health checks and
// service managers (exit 0 only when SERVING).
#include <iostream>
#include <memory>
#include <string>

#include "client/command.hpp"
#include "client/remote/cli_support.hpp"
#include "client/remote/remote_client.hpp"

namespace kessler::cli {
namespace {

struct HealthOptions {
  std::string service;
  double timeout_s = 5;
};

int health(const HealthOptions& o, const GlobalOptions& global) {
  OutputFormat format;
  if (!resolve_output("health", global.output, {"table", "json"}, format)) return kExitUsage;
  RemoteClient client(server_address(global.server));
  std::string status;
  CallResult r = client.health(o.service, o.timeout_s, status);
  if (!r.ok) {
    std::cerr << "kessler health: " << r.describe() << "\n";
    return kExitFailure;
  }
  if (format == OutputFormat::kJson) {
    JsonObject json;
    json.add("server", client.address()).add("service", o.service).add("status", status);
    if (!r.warning.empty()) json.add("warning", r.warning);
    std::cout << json.str() << "\n";
  } else {
    std::cout << status << "\n";
    if (!r.warning.empty()) std::cout << "warning: " << r.warning << "\n";
  }
  return status == "SERVING" ? kExitOk : kExitFailure;
}

}  // namespace

CommandRun setup_health(CLI::App& command, GlobalOptions& global) {
  auto o = std::make_shared<HealthOptions>();
  command
      .add_option("--service", o->service,
                  "a service by name, e.g. kessler.v1.KesslerService (default: the whole server)")
      ->option_text("NAME");
  command.add_option("--timeout-s", o->timeout_s, "give up after S seconds (default 5)")
      ->option_text("S")
      ->check(positive_number());
  add_global_options(command, global, "table (default) or json");
  command.footer(
      "Asks kesslerd's standard health service (grpc.health.v1.Health/Check) and prints the answer: SERVING "
      "(exit 0), NOT_SERVING (exit 1, e.g. while it shuts down). A daemon that cannot be reached, or a "
      "service "
      "it does not know, exits 1 too.");
  return [o, &global] { return health(*o, global); };
}

}  // namespace kessler::cli
