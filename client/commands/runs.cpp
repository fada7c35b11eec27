// kessler runs: the daemon's runs, newest first, as a table, CSV or JSON.
#include <iostream>
#include <memory>
#include <sstream>

#include "client/command.hpp"
#include "client/remote/cli_support.hpp"
#include "client/remote/remote_client.hpp"
#include "core/time/epoch.hpp"

namespace kessler::cli {
namespace {

struct RunsOptions {
  std::vector<std::string> states;
  std::uint64_t limit = 50;
};

void print_json(const std::vector<v1::Run>& runs) {
  std::cout << "[";
  for (std::size_t i = 0; i < runs.size(); ++i) {
    JsonObject obj;
    obj.add("run_id", static_cast<std::int64_t>(runs[i].id()))
        .add("name", runs[i].name())
        .add("state", v1::run_state_name(runs[i].state()))
        .add("created", unix_time_text(runs[i].created_unix_s()))
        .add("started", unix_time_text(runs[i].started_unix_s()))
        .add("finished", unix_time_text(runs[i].finished_unix_s()))
        .add("events", static_cast<std::uint64_t>(runs[i].summary().events()))
        .add("error", runs[i].error());
    std::cout << (i ? ",\n " : "") << obj.str();
  }
  std::cout << "]\n";
}

void print_rows(const std::vector<v1::Run>& runs, OutputFormat format) {
  std::vector<std::string> header = {"ID", "NAME", "STATE", "CREATED", "FINISHED", "EVENTS", "CONJ", "COLL"};
  std::vector<std::vector<std::string>> rows;
  for (const auto& run : runs) {
    const auto& s = run.summary();
    bool ended = run.has_summary();
    rows.push_back({std::to_string(run.id()), run.name().empty() ? "-" : run.name(),
                    v1::run_state_name(run.state()), unix_time_text(run.created_unix_s()),
                    unix_time_text(run.finished_unix_s()), ended ? std::to_string(s.events()) : "-",
                    ended ? std::to_string(s.conjunctions()) : "-",
                    ended ? std::to_string(s.collisions()) : "-"});
  }
  if (format == OutputFormat::kCsv) {
    for (std::size_t i = 0; i < header.size(); ++i) std::cout << (i ? "," : "") << header[i];
    std::cout << "\n";
    for (const auto& row : rows) {
      for (std::size_t i = 0; i < row.size(); ++i) std::cout << (i ? "," : "") << csv_field(row[i]);
      std::cout << "\n";
    }
  } else if (rows.empty()) {
    std::cout << "no runs\n";
  } else {
    std::cout << render_table(header, rows);
  }
}

int list_runs(const RunsOptions& o, const GlobalOptions& global) {
  OutputFormat format;
  if (!resolve_output("runs", global.output, {"table", "csv", "json"}, format)) return kExitUsage;
  v1::ListRunsRequest request;
  for (const std::string& s : o.states) {
    v1::RunState state = v1::RUN_STATE_UNSPECIFIED;
    for (int v = 1; v <= 5; ++v)
      if (s == v1::run_state_name(static_cast<v1::RunState>(v))) state = static_cast<v1::RunState>(v);
    if (state == v1::RUN_STATE_UNSPECIFIED) return usage_error("runs", "--state: unknown state '" + s + "'");
    request.add_states(state);
  }
  RemoteClient client(server_address(global.server));
  std::vector<v1::Run> runs;
  while (runs.size() < o.limit) {
    request.set_page_size(static_cast<int>(std::min<std::uint64_t>(o.limit - runs.size(), 1000)));
    v1::ListRunsResponse response;
    CallResult r = client.list(request, response);
    if (!r.ok) {
      std::cerr << "kessler runs: " << r.describe() << "\n";
      return r.exit_code();
    }
    for (const auto& run : response.runs()) runs.push_back(run);
    if (response.next_page_token().empty()) break;
    request.set_page_token(response.next_page_token());
  }
  if (format == OutputFormat::kJson)
    print_json(runs);
  else
    print_rows(runs, format);
  return kExitOk;
}

}  // namespace

CommandRun setup_runs(CLI::App& command, GlobalOptions& global) {
  auto o = std::make_shared<RunsOptions>();
  command
      .add_option("--state", o->states,
                  "only these states, comma-separated: queued, running, succeeded, failed, cancelled")
      ->option_text("STATES")
      ->delimiter(',');
  command.add_option("--limit", o->limit, "at most N runs (default 50)")
      ->option_text("N")
      ->check(CLI::Range(std::uint64_t{1}, std::uint64_t{1} << 40));
  add_global_options(command, global, "table (default), csv or json (an array of runs)");
  command.footer(
      "Lists runs, newest first."
      "\n\n"
      "example:\n  kessler runs --state running,queued");
  return [o, &global] { return list_runs(*o, global); };
}

}  // namespace kessler::cli
