// kessler health: the daemon's standard health check, for scripts, container health checks and
// service managers (exit 0 only when SERVING).
#include <iostream>
#include <string>

#include "client/command.hpp"
#include "client/remote/cli_support.hpp"
#include "client/remote/remote_client.hpp"

namespace kessler::cli {
namespace {

int health_main(int argc, char** argv) {
  Options o;
  std::string error;
  if (!o.parse(argc, argv, {{"--service"}, {"--timeout-s"}}, error)) return usage_error("health", error);
  if (o.has("--help")) {
    std::cout << "usage: kessler health [--service NAME] [--timeout-s S] [--output table|json]\n\n"
                 "Asks kesslerd's standard health service (grpc.health.v1.Health/Check) and prints the\n"
                 "answer: SERVING (exit 0), NOT_SERVING (exit 1, e.g. while it shuts down). A daemon that\n"
                 "cannot be reached, or a service it does not know, exits 1 too.\n\noptions:\n"
                 "  --service NAME       a service by name, e.g. kessler.v1.KesslerService (default: the\n"
                 "                       whole server)\n"
                 "  --timeout-s S        give up after S seconds (default 5)\n"
                 "  --server HOST:PORT   kesslerd to ask (default $KESSLER_SERVER, else 127.0.0.1:50051)\n";
    return kExitOk;
  }
  if (!o.positional.empty()) return usage_error("health", "takes no arguments");
  double timeout_s = 5;
  if (o.has("--timeout-s") && (!parse_double(o.get("--timeout-s"), timeout_s) || timeout_s <= 0))
    return usage_error("health", "--timeout-s must be a positive number of seconds");
  auto format = parse_output(o.get("--output", "table"));
  if (!format || *format == OutputFormat::kCsv)
    return usage_error("health", "--output must be table or json");
  const std::string service = o.get("--service");
  RemoteClient client(server_address(o.get("--server")));
  std::string status;
  CallResult r = client.health(service, timeout_s, status);
  if (!r.ok) {
    std::cerr << "kessler health: " << r.describe() << "\n";
    return kExitFailure;
  }
  if (*format == OutputFormat::kJson)
    std::cout
        << JsonObject().add("server", client.address()).add("service", service).add("status", status).str()
        << "\n";
  else
    std::cout << status << "\n";
  return status == "SERVING" ? kExitOk : kExitFailure;
}

}  // namespace

KESSLER_COMMAND("health", 27, "health [--service NAME]", "the daemon's health check: exit 0 when SERVING",
                health_main);

}  // namespace kessler::cli
