// kessler submit FILE: queues a run of a scenario on kesslerd and, with --watch, follows it to its end.
#include <fstream>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>

#include "client/command.hpp"
#include "client/commands/follow.hpp"
#include "client/remote/cli_support.hpp"
#include "client/remote/remote_client.hpp"
#include "core/scenario/run_builder.hpp"

namespace kessler::cli {
namespace {

struct SubmitOptions {
  std::string scenario_path, catalog_path;
  bool watch = false;
  int threads = -1;  // -1: not given (the daemon's --threads)
  WatchOptions follow;
};

bool read_file(const std::string& path, std::string& out) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  std::ostringstream s;
  s << in.rdbuf();
  out = s.str();
  return true;
}

// The request for the scenario file, with --catalog's text as its inline catalog. nullopt, else the
// exit code after the error is printed.
std::optional<int> make_request(const SubmitOptions& o, v1::SubmitRunRequest& request) {
  std::string text;
  if (!read_file(o.scenario_path, text)) return usage_error("submit", "cannot read " + o.scenario_path);
  if (!o.catalog_path.empty()) {
    std::string catalog;
    if (!read_file(o.catalog_path, catalog)) return usage_error("submit", "cannot read " + o.catalog_path);
    v1::Scenario scenario;
    if (auto e = parse_scenario(text, scenario)) {
      std::cerr << "kessler submit: " << o.scenario_path << ": " << e->message() << "\n";
      return kExitUsage;
    }
    scenario.mutable_population()->mutable_catalog()->set_text(std::move(catalog));
    *request.mutable_scenario() = std::move(scenario);
  } else {
    request.set_scenario_text(text);
  }
  if (o.threads >= 0) request.set_threads(o.threads);
  return std::nullopt;
}

int submit(const SubmitOptions& o, const GlobalOptions& global) {
  OutputFormat format;
  if (!resolve_output("submit", global.output, {"table", "json"}, format)) return kExitUsage;
  v1::SubmitRunRequest request;
  if (auto exit = make_request(o, request)) return *exit;
  RemoteClient client(server_address(global.server));
  v1::Run run;
  CallResult r = client.submit(request, run);
  if (!r.ok) {
    std::cerr << "kessler submit: " << o.scenario_path << ": " << r.describe() << "\n";
    return r.exit_code();
  }
  if (o.watch) {
    if (format != OutputFormat::kJson) std::cerr << "run " << run.id() << " submitted\n";
    return follow_run(client, run.id(), o.follow, format);
  }
  if (format == OutputFormat::kJson)
    std::cout << JsonObject()
                     .add("run_id", static_cast<std::int64_t>(run.id()))
                     .add("state", v1::run_state_name(run.state()))
                     .str()
              << "\n";
  else
    std::cout << "run " << run.id() << " " << v1::run_state_name(run.state())
              << (run.queue_position() > 0 ? " (position " + std::to_string(run.queue_position()) + ")" : "")
              << "\n";
  return kExitOk;
}

}  // namespace

CommandRun setup_submit(CLI::App& command, GlobalOptions& global) {
  auto o = std::make_shared<SubmitOptions>();
  command.add_option("FILE", o->scenario_path, "the scenario file")->required();
  command.add_flag("--watch", o->watch, "follow the run to its end; exit 0 when it succeeds, 1 otherwise");
  command
      .add_option("--catalog", o->catalog_path,
                  "use FILE's text as the scenario's inline catalog (population.catalog.text; TLE or OMM)")
      ->option_text("FILE");
  command.add_option("--threads", o->threads, "OpenMP threads of this run (default: the daemon's --threads)")
      ->option_text("N")
      ->check(CLI::Range(0, 1024));
  add_watch_options(command, o->follow);
  add_global_options(command, global, kWatchOutputHelp);
  command.footer(
      "Sends the scenario in FILE (YAML or JSON) to kesslerd, which validates it and queues a run. Prints "
      "the "
      "run's id; with --watch, follows the run live to its end like 'kessler watch'."
      "\n\n"
      "examples:\n"
      "  kessler submit deploy/scenarios/paper-1day.yaml --watch\n"
      "  kessler submit my.yaml --catalog tles.txt --output json");
  return [o, &global] { return submit(*o, global); };
}

}  // namespace kessler::cli
