// kessler ensemble show|list|cancel: Monte Carlo ensembles (kessler submit --members N queues them).
#include <iostream>
#include <memory>
#include <sstream>

#include "client/command.hpp"
#include "client/remote/cli_support.hpp"
#include "client/remote/remote_client.hpp"

namespace kessler::cli {
namespace {

struct EnsembleOptions {
  std::int64_t id = 0;
  std::vector<double> kappas;
  std::uint64_t limit = 50;
};

std::string number(double v) {
  std::ostringstream s;
  s.precision(10);
  s << v;
  return s.str();
}

std::string member_json(const v1::EnsembleMember& m) {
  return JsonObject()
      .add("run_id", static_cast<std::int64_t>(m.run_id()))
      .add("member_index", static_cast<std::uint64_t>(m.member_index()))
      .add("seed", static_cast<std::uint64_t>(m.seed()))
      .add("state", v1::run_state_name(m.state()))
      .add("events_digest", m.events_digest())
      .str();
}

std::string json_numbers(const google::protobuf::RepeatedField<double>& values) {
  std::string out;
  for (double v : values) out += (out.empty() ? "" : ",") + json_number(v);
  return "[" + out + "]";
}

std::string sample_json(const v1::EnsembleSample& s) {
  return JsonObject()
      .add("t", s.t())
      .add("objects_mean", s.objects_mean())
      .add("objects_median", s.objects_median())
      .add("objects_p05", s.objects_p05())
      .add("objects_p95", s.objects_p95())
      .add("payload_mean", s.payload_mean())
      .add("rocket_body_mean", s.rocket_body_mean())
      .add("debris_mean", s.debris_mean())
      .add("unknown_mean", s.unknown_mean())
      .add("fragments_mean", s.fragments_mean())
      .add("collisions_mean", s.collisions_mean())
      .add("catastrophic_mean", s.catastrophic_mean())
      .add_raw("conjunctions_mean", json_numbers(s.conjunctions_mean()))
      .add_raw("conjunctions_p05", json_numbers(s.conjunctions_p05()))
      .add_raw("conjunctions_p95", json_numbers(s.conjunctions_p95()))
      .str();
}

// The ensemble's head fields (the list's row), to which show adds members and series.
JsonObject head_json(const v1::EnsembleReport& e) {
  JsonObject obj;
  obj.add("ensemble_id", static_cast<std::int64_t>(e.id()))
      .add("name", e.name())
      .add("state", v1::run_state_name(e.state()))
      .add("members", static_cast<std::uint64_t>(e.members()))
      .add("finished", static_cast<std::uint64_t>(e.finished()))
      .add("aggregated", static_cast<std::uint64_t>(e.aggregated()))
      .add("base_seed", static_cast<std::uint64_t>(e.base_seed()));
  return obj;
}

void print_show_json(const v1::EnsembleReport& e) {
  std::string members, series;
  for (const auto& m : e.member()) members += (members.empty() ? "" : ",") + member_json(m);
  for (const auto& s : e.series()) series += (series.empty() ? "" : ",") + sample_json(s);
  std::cout << head_json(e)
                   .add_raw("kappas", json_numbers(e.kappas()))
                   .add_raw("member_runs", "[" + members + "]")
                   .add_raw("series", "[" + series + "]")
                   .str()
            << "\n";
}

std::vector<std::string> series_header(const v1::EnsembleReport& e, bool all) {
  std::vector<std::string> h = {"t_s", "objects_mean", "objects_median", "objects_p05", "objects_p95"};
  if (all)
    for (const char* c :
         {"payload_mean", "rocket_body_mean", "debris_mean", "unknown_mean", "fragments_mean"})
      h.push_back(c);
  h.push_back("collisions_mean");
  h.push_back("catastrophic_mean");
  for (double k : e.kappas()) h.push_back("conj_kappa_" + number(k) + "_mean");
  if (all)
    for (const char* stat : {"_p05", "_p95"})
      for (double k : e.kappas()) h.push_back("conj_kappa_" + number(k) + stat);
  return h;
}

std::vector<std::string> series_row(const v1::EnsembleSample& s, bool all) {
  std::vector<std::string> row = {number(s.t()), number(s.objects_mean()), number(s.objects_median()),
                                  number(s.objects_p05()), number(s.objects_p95())};
  if (all)
    for (double v :
         {s.payload_mean(), s.rocket_body_mean(), s.debris_mean(), s.unknown_mean(), s.fragments_mean()})
      row.push_back(number(v));
  row.push_back(number(s.collisions_mean()));
  row.push_back(number(s.catastrophic_mean()));
  for (double c : s.conjunctions_mean()) row.push_back(number(c));
  if (all) {
    for (double c : s.conjunctions_p05()) row.push_back(number(c));
    for (double c : s.conjunctions_p95()) row.push_back(number(c));
  }
  return row;
}

void print_show(const v1::EnsembleReport& e, OutputFormat format) {
  if (format == OutputFormat::kJson) return print_show_json(e);
  const bool csv = format == OutputFormat::kCsv;
  std::vector<std::vector<std::string>> rows;
  for (const auto& s : e.series()) rows.push_back(series_row(s, csv));
  const auto header = series_header(e, csv);
  if (csv) {
    for (std::size_t i = 0; i < header.size(); ++i) std::cout << (i ? "," : "") << header[i];
    std::cout << "\n";
    for (const auto& row : rows) {
      for (std::size_t i = 0; i < row.size(); ++i) std::cout << (i ? "," : "") << row[i];
      std::cout << "\n";
    }
    return;
  }
  std::cout << "ensemble " << e.id() << (e.name().empty() ? "" : " (" + e.name() + ")") << ": "
            << v1::run_state_name(e.state()) << ", " << e.finished() << "/" << e.members()
            << " members finished, " << e.aggregated() << " aggregated, seeds " << e.base_seed() << ".."
            << e.base_seed() + e.members() - 1 << "\n";
  if (rows.empty())
    std::cout << "no aggregates yet (no member has succeeded)\n";
  else
    std::cout << render_table(header, rows);
}

int show(const EnsembleOptions& o, const GlobalOptions& global) {
  OutputFormat format;
  if (!resolve_output("ensemble show", global.output, {"table", "csv", "json"}, format)) return kExitUsage;
  RemoteClient client(server_address(global.server));
  v1::GetEnsembleRequest request;
  request.set_ensemble_id(o.id);
  for (double k : o.kappas) request.add_kappas(k);
  v1::EnsembleReport e;
  CallResult r = client.get_ensemble(request, e);
  if (!r.ok) {
    std::cerr << "kessler ensemble show: " << r.describe() << "\n";
    return r.exit_code();
  }
  print_show(e, format);
  return kExitOk;
}

int list(const EnsembleOptions& o, const GlobalOptions& global) {
  OutputFormat format;
  if (!resolve_output("ensemble list", global.output, {"table", "csv", "json"}, format)) return kExitUsage;
  RemoteClient client(server_address(global.server));
  v1::ListEnsemblesRequest request;
  request.set_page_size(static_cast<int>(std::min<std::uint64_t>(o.limit, 1000)));
  v1::ListEnsemblesResponse response;
  CallResult r = client.list_ensembles(request, response);
  if (!r.ok) {
    std::cerr << "kessler ensemble list: " << r.describe() << "\n";
    return r.exit_code();
  }
  if (format == OutputFormat::kJson) {
    std::cout << "[";
    for (int i = 0; i < response.ensembles_size(); ++i)
      std::cout << (i ? ",\n " : "") << head_json(response.ensembles(i)).str();
    std::cout << "]\n";
    return kExitOk;
  }
  const std::vector<std::string> header = {"ID",       "NAME",       "STATE", "MEMBERS",
                                           "FINISHED", "AGGREGATED", "SEEDS"};
  std::vector<std::vector<std::string>> rows;
  for (const auto& e : response.ensembles())
    rows.push_back({std::to_string(e.id()), e.name().empty() ? "-" : e.name(), v1::run_state_name(e.state()),
                    std::to_string(e.members()), std::to_string(e.finished()), std::to_string(e.aggregated()),
                    std::to_string(e.base_seed()) + ".." + std::to_string(e.base_seed() + e.members() - 1)});
  if (format == OutputFormat::kCsv) {
    for (std::size_t i = 0; i < header.size(); ++i) std::cout << (i ? "," : "") << header[i];
    std::cout << "\n";
    for (const auto& row : rows) {
      for (std::size_t i = 0; i < row.size(); ++i) std::cout << (i ? "," : "") << csv_field(row[i]);
      std::cout << "\n";
    }
  } else if (rows.empty()) {
    std::cout << "no ensembles\n";
  } else {
    std::cout << render_table(header, rows);
  }
  return kExitOk;
}

int cancel(const EnsembleOptions& o, const GlobalOptions& global) {
  OutputFormat format;
  if (!resolve_output("ensemble cancel", global.output, {"table", "json"}, format)) return kExitUsage;
  RemoteClient client(server_address(global.server));
  v1::EnsembleReport e;
  CallResult r = client.cancel_ensemble(o.id, e);
  if (!r.ok) {
    std::cerr << "kessler ensemble cancel: " << r.describe() << "\n";
    return r.exit_code();
  }
  if (format == OutputFormat::kJson)
    std::cout << head_json(e).str() << "\n";
  else
    std::cout << "ensemble " << o.id << " " << v1::run_state_name(e.state())
              << " (running members stop at the end of their current step)\n";
  return kExitOk;
}

CLI::Option* add_ensemble_id(CLI::App& command, std::int64_t& id) {
  return command.add_option("ID", id, "the ensemble's id (kessler ensemble list lists them)")
      ->required()
      ->check(CLI::Validator(
          [](std::string& text) {
            return !text.empty() && text.find_first_not_of("0123456789") == std::string::npos &&
                           text.find_first_not_of('0') != std::string::npos
                       ? std::string()
                       : "must be an ensemble id (a positive integer), got '" + text + "'";
          },
          "ID", "ensemble id"));
}

}  // namespace

CommandRun setup_ensemble(CLI::App& command, GlobalOptions& global) {
  auto o = std::make_shared<EnsembleOptions>();
  command.require_subcommand(1);
  CLI::App* show_cmd = command.add_subcommand("show", "the ensemble's members and aggregates over time");
  add_ensemble_id(*show_cmd, o->id);
  show_cmd
      ->add_option("--kappas", o->kappas, "kappa thresholds of the conjunction columns (default 1 2 5 10)")
      ->check(positive_number());
  add_global_options(*show_cmd, global, "table (default), csv (one row per sample, every column) or json");
  CLI::App* list_cmd = command.add_subcommand("list", "ensembles, newest first");
  list_cmd->add_option("--limit", o->limit, "at most this many (default 50, at most 1000)")->option_text("N");
  add_global_options(*list_cmd, global, "table (default), csv or json");
  CLI::App* cancel_cmd = command.add_subcommand("cancel", "cancel every member that has not ended");
  add_ensemble_id(*cancel_cmd, o->id);
  add_global_options(*cancel_cmd, global, "table (default) or json");
  command.footer(
      "An ensemble is N runs of one scenario, member k with the scenario's seed + k ('kessler submit FILE "
      "--members N'). 'show' aggregates the members that have succeeded at their common progress times: "
      "objects on orbit (mean, median, 5th and 95th percentiles by linear interpolation between order "
      "statistics), by type (means), cumulative collisions, catastrophic collisions and conjunctions per "
      "kappa threshold (means). Each member is a run: 'kessler show RUN' and the other run commands take "
      "its id.");
  return [o, &global, show_cmd, list_cmd, cancel_cmd] {
    if (show_cmd->parsed()) return show(*o, global);
    if (list_cmd->parsed()) return list(*o, global);
    if (cancel_cmd->parsed()) return cancel(*o, global);
    return usage_error("ensemble", "a subcommand is required: show, list or cancel");
  };
}

}  // namespace kessler::cli
