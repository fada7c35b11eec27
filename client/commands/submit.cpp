// kessler submit FILE: queues a run of a scenario on kesslerd and, with --watch, follows it to its end;
// with --members N (or a scenario with an ensemble) queues a Monte Carlo ensemble of N runs instead.
#include <chrono>
#include <fstream>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>
#include <thread>

#include "client/command.hpp"
#include "client/commands/follow.hpp"
#include "client/remote/cli_support.hpp"
#include "client/remote/remote_client.hpp"
#include "core/scenario/input_file.hpp"
#include "core/scenario/run_builder.hpp"

namespace kessler::cli {
namespace {

struct SubmitOptions {
  std::string scenario_path, catalog_path;
  bool watch = false;
  int threads = -1;           // -1: not given (the daemon's --threads)
  std::int64_t members = -1;  // -1: not given (the scenario's ensemble, if any)
  std::string request_id;     // empty: a fresh one
  WatchOptions follow;
};

// A regular text file only (core/scenario/input_file.hpp); otherwise *why says what it is.
bool read_file(const std::string& path, std::string& out, std::string& why) {
  auto text = read_input_file(path, &why);
  if (!text) return false;
  out = std::move(*text);
  return true;
}

// The request for the scenario file, with --catalog's text as its inline catalog. nullopt, else the
// exit code after the error is printed.
std::optional<int> make_request(const SubmitOptions& o, v1::SubmitRunRequest& request) {
  std::string text, why;
  if (!read_file(o.scenario_path, text, why)) return usage_error("submit", o.scenario_path + " " + why);
  if (!o.catalog_path.empty()) {
    std::string catalog;
    if (!read_file(o.catalog_path, catalog, why)) return usage_error("submit", o.catalog_path + " " + why);
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

// Whether the request is for an ensemble: --members, or a scenario that asks for one (a scenario the
// CLI cannot parse goes to SubmitRun, which says what is wrong with it).
bool wants_ensemble(const SubmitOptions& o, const v1::SubmitRunRequest& request) {
  if (o.members >= 0) return true;
  if (request.has_scenario()) return request.scenario().has_ensemble();
  v1::Scenario scenario;
  return !parse_scenario(request.scenario_text(), scenario) && scenario.has_ensemble();
}

// Sends the submission until it is answered: a daemon away or an answer lost (UNAVAILABLE,
// DEADLINE_EXCEEDED) is tried again with the same request id for up to --retry-s seconds, so a
// retry that reaches a daemon which had queued the first try gets that run back, not a second one.
template <typename Call>
CallResult submit_with_retry(const SubmitOptions& o, Call&& call) {
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::duration<double>(o.follow.retry_s);
  for (;;) {
    CallResult r = call();
    if (r.ok || !r.retryable() || std::chrono::steady_clock::now() >= give_up) return r;
    std::this_thread::sleep_for(std::chrono::seconds(1));
  }
}

int submit_ensemble(const SubmitOptions& o, const v1::SubmitRunRequest& run_request, OutputFormat format,
                    RemoteClient& client) {
  if (o.watch)
    return usage_error("submit", "--watch follows one run; an ensemble's members are runs to watch");
  v1::SubmitEnsembleRequest request;
  if (run_request.has_scenario())
    *request.mutable_scenario() = run_request.scenario();
  else
    request.set_scenario_text(run_request.scenario_text());
  request.set_threads(run_request.threads());
  request.set_request_id(run_request.request_id());
  if (o.members > 0) request.set_members(static_cast<std::uint64_t>(o.members));
  v1::EnsembleReport ensemble;
  CallResult r = submit_with_retry(o, [&] { return client.submit_ensemble(request, ensemble); });
  if (!r.ok) {
    std::cerr << "kessler submit: " << o.scenario_path << ": " << r.describe() << "\n";
    return r.exit_code();
  }
  std::string run_ids;
  for (const auto& m : ensemble.member())
    run_ids += (run_ids.empty() ? "" : ",") + std::to_string(m.run_id());
  if (format == OutputFormat::kJson)
    std::cout << JsonObject()
                     .add("ensemble_id", static_cast<std::int64_t>(ensemble.id()))
                     .add("members", static_cast<std::uint64_t>(ensemble.members()))
                     .add("base_seed", static_cast<std::uint64_t>(ensemble.base_seed()))
                     .add("state", v1::run_state_name(ensemble.state()))
                     .add_raw("run_ids", "[" + run_ids + "]")
                     .str()
              << "\n";
  else
    std::cout << "ensemble " << ensemble.id() << " " << v1::run_state_name(ensemble.state()) << ": "
              << ensemble.members() << " members, seeds " << ensemble.base_seed() << ".."
              << ensemble.base_seed() + ensemble.members() - 1 << ", runs " << run_ids << "\n";
  return kExitOk;
}

int submit(const SubmitOptions& o, const GlobalOptions& global) {
  OutputFormat format;
  if (!resolve_output("submit", global.output, {"table", "json"}, format)) return kExitUsage;
  if (o.members == 0) {
    std::cerr << "kessler submit: ensemble.members: must be at least 1, got 0\n";
    return kExitUsage;
  }
  v1::SubmitRunRequest request;
  if (auto exit = make_request(o, request)) return *exit;
  request.set_request_id(o.request_id.empty() ? new_request_id() : o.request_id);
  RemoteClient client(server_address(global.server));
  if (wants_ensemble(o, request)) return submit_ensemble(o, request, format, client);
  v1::Run run;
  CallResult r = submit_with_retry(o, [&] { return client.submit(request, run); });
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
  command
      .add_option("--members", o->members,
                  "queue a Monte Carlo ensemble of N runs, member k with the scenario's seed + k (overrides "
                  "the scenario's ensemble.members)")
      ->option_text("N")
      ->check(CLI::NonNegativeNumber);
  command
      .add_option("--request-id", o->request_id,
                  "the submission's id (default: a fresh random one); sending the same id again returns the "
                  "run it made instead of queueing another")
      ->option_text("ID");
  add_watch_options(command, o->follow);
  add_global_options(command, global, kWatchOutputHelp);
  command.footer(
      "Sends the scenario in FILE (YAML or JSON) to kesslerd, which validates it and queues a run. Prints "
      "the "
      "run's id; with --watch, follows the run live to its end like 'kessler watch'. With --members N, or "
      "a scenario with ensemble.members, queues an ensemble of N runs that differ only in their seed and "
      "prints the ensemble's id ('kessler ensemble show ID' aggregates the members). A submission the "
      "daemon did not answer (away, or the answer lost) is sent again with the same request id for up to "
      "--retry-s seconds: a retry never queues a second run."
      "\n\n"
      "examples:\n"
      "  kessler submit deploy/scenarios/paper-1day.yaml --watch\n"
      "  kessler submit my.yaml --catalog tles.txt --output json\n"
      "  kessler submit my.yaml --members 100 --output json   (then: kessler ensemble show ID)");
  return [o, &global] { return submit(*o, global); };
}

}  // namespace kessler::cli
