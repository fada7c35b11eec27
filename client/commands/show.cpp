// kessler show RUN: a run's scenario, ingest report, state, times, phase timers, conjunction counts by
// kappa over time, the traffic's launches, ends of life and disposals, objects alive by type over time
// the population's key numbers at its first and newest snapshots, and its summary.
#include <algorithm>
#include <cstdio>
#include <iostream>
#include <memory>

#include "client/command.hpp"
#include "client/commands/show_population.hpp"
#include "client/remote/cli_support.hpp"
#include "client/remote/remote_client.hpp"
#include "client/render.hpp"
#include "core/time/epoch.hpp"

namespace kessler::cli {
namespace {

struct ShowOptions {
  std::int64_t run_id = 0;
  std::vector<double> kappas;
  double bin_s = 0;  // 0: the run's length / 24
};

void print_header(const v1::Run& run) {
  std::cout << "run " << run.id() << (run.name().empty() ? "" : " (" + run.name() + ")") << ": "
            << v1::run_state_name(run.state()) << "\n";
  if (!run.error().empty()) std::cout << "  error     " << run.error() << "\n";
  if (run.ensemble_id() != 0)
    std::cout << "  ensemble  " << run.ensemble_id() << ", member " << run.member_index() << " (seed "
              << run.scenario().seed() << ")\n";
  std::cout << "  created   " << unix_time_text(run.created_unix_s()) << "\n"
            << "  started   " << unix_time_text(run.started_unix_s()) << "\n"
            << "  finished  " << unix_time_text(run.finished_unix_s()) << "\n"
            << "  threads   " << (run.threads() ? std::to_string(run.threads()) : "daemon default") << "\n";
  if (run.has_progress())
    std::cout << "  progress  " << progress_percent(run.progress()) << " (step " << run.progress().step()
              << " of " << run.progress().total_steps() << "), last event " << run.last_seq() << "\n";
  std::cout << "\nscenario\n  " << to_json(run.scenario()) << "\n";
  if (run.has_ingest()) std::cout << "\n" << ingest_table(ingest_outcome_of(run.ingest()));
}

void print_timers(const v1::PhaseTimers& t) {
  std::vector<std::vector<std::string>> rows;
  auto add = [&](const char* name, double s) {
    char a[32], b[32];
    std::snprintf(a, sizeof a, "%.3f", s);
    std::snprintf(b, sizeof b, "%.1f%%", t.total_s() > 0 ? 100 * s / t.total_s() : 0.0);
    rows.push_back({std::string("  ") + name, a, b});
  };
  add("integrator", t.integrator_s());
  add("burn-up", t.burn_up_s());
  add("grid", t.grid_s());
  add("detection", t.detection_s());
  add("output", t.output_s());
  add("checkpoint", t.checkpoint_s());
  add("total", t.total_s());
  std::cout << "\ntimers\n" << render_table({"  PHASE", "SECONDS", "SHARE"}, rows);
}

void print_kappa_bins(const v1::Run& run, const v1::RunStats& stats) {
  std::cout << "\nconjunctions by kappa (cumulative, per " << format_duration(stats.time_bin_s())
            << " bin)\n";
  std::vector<std::string> header = {"  FROM"};
  for (const auto& series : stats.by_kappa()) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "k<=%g", series.kappa());
    header.push_back(buf);
  }
  std::vector<std::vector<std::string>> rows;
  for (int b = 0; b < stats.bin_start_s_size(); ++b) {
    std::vector<std::string> row = {"  " +
                                    format_sim_time(run.scenario().start_epoch(), stats.bin_start_s(b))};
    for (const auto& series : stats.by_kappa())
      row.push_back(b < series.cumulative_size() ? std::to_string(series.cumulative(b)) : "-");
    rows.push_back(row);
  }
  std::cout << render_table(header, rows);
  std::cout << "  total: " << stats.conjunctions() << " conjunctions, " << stats.collisions()
            << " collisions, " << stats.evasions() << " evasions, " << stats.burn_ups() << " burn-ups, "
            << stats.breakups() << " breakups (" << stats.fragments() << " fragments)\n";
  if (stats.launches() + stats.ends_of_life() > 0)
    std::cout << "  traffic: " << stats.launched_objects() << " objects launched (" << stats.launches()
              << " launches), " << stats.ends_of_life() << " ends of life, " << stats.disposals()
              << " disposals, " << stats.disposals_failed() << " failed disposals, " << stats.deorbits()
              << " de-orbits\n";
  std::cout << "\n";
}

// Objects alive by type over the run: at most 13 of the progress samples, evenly spaced, the last
// included.
void print_alive(const v1::Run& run, const v1::RunStats& stats) {
  const int n = stats.objects_alive_size();
  if (n == 0) return;
  std::vector<std::vector<std::string>> rows;
  const int stride = std::max(1, (n + 11) / 12);
  for (int i = 0; i < n; i += stride) {
    const int k = (i + stride >= n) ? n - 1 : i;
    const v1::AliveSample& a = stats.objects_alive(k);
    const v1::ObjectCounts& t = a.by_type();
    rows.push_back({"  " + format_sim_time(run.scenario().start_epoch(), a.sim_time_s()),
                    std::to_string(a.objects_alive()), std::to_string(t.payload()),
                    std::to_string(t.rocket_body()), std::to_string(t.debris()), std::to_string(t.unknown()),
                    std::to_string(t.fragments())});
    if (k == n - 1) break;
  }
  std::cout << "objects alive by type\n"
            << render_table({"  TIME", "ALIVE", "PAYLOAD", "ROCKET BODY", "DEBRIS", "UNKNOWN", "FRAGMENTS"},
                            rows)
            << "\n";
}

int show(const ShowOptions& o, const GlobalOptions& global) {
  OutputFormat format;
  if (!resolve_output("show", global.output, {"table", "json"}, format)) return kExitUsage;
  v1::GetRunStatsRequest stats_request;
  stats_request.set_run_id(o.run_id);
  for (double k : o.kappas) stats_request.add_kappas(k);
  if (o.bin_s > 0) stats_request.set_time_bin_s(o.bin_s);
  RemoteClient client(server_address(global.server));
  v1::Run run;
  v1::RunStats stats;
  CallResult r = client.get(o.run_id, run);
  if (r.ok) r = client.stats(stats_request, stats);
  if (!r.ok) {
    std::cerr << "kessler show: " << r.describe() << "\n";
    return r.exit_code();
  }
  // An inline catalog can be megabytes: the daemon leaves it out of GetRun and says its size.
  if (run.scenario().population().has_catalog()) {
    auto* catalog = run.mutable_scenario()->mutable_population()->mutable_catalog();
    catalog->set_text("<" + std::to_string(run.inline_data_omitted_bytes()) + " bytes inline>");
  }
  if (format == OutputFormat::kJson) {
    std::cout << JsonObject().add_raw("run", to_json(run)).add_raw("stats", to_json(stats)).str() << "\n";
    std::cout << summary_json(run) << std::endl;
    return kExitOk;
  }
  print_header(run);
  if (run.has_summary()) print_timers(run.summary().timers());
  print_kappa_bins(run, stats);
  print_alive(run, stats);
  print_population(client, o.run_id);
  std::cout << summary_text(run);
  return kExitOk;
}

}  // namespace

CommandRun setup_show(CLI::App& command, GlobalOptions& global) {
  auto o = std::make_shared<ShowOptions>();
  add_run_id(command, o->run_id);
  command
      .add_option("--kappas", o->kappas, "kappa thresholds to count at, comma-separated (default 1,2,5,10)")
      ->option_text("LIST")
      ->delimiter(',')
      ->check(positive_number());
  command.add_option("--bin-s", o->bin_s, "width of a time bin in seconds (default: the run's length / 24)")
      ->option_text("S")
      ->check(positive_number());
  add_global_options(command, global,
                     "table (default) or json: one line with the run and its stats, then the run's summary "
                     "object (the same keys as 'run --local') last");
  command.footer(
      "Shows a run: its scenario, the ingest report of its catalog, state, times, phase timers, conjunction "
      "counts by kappa over time, launches, ends of life and disposals (runs with traffic), the population "
      "at its first and newest snapshots (objects by kind and status, median sizes, the spatial density's "
      "peak) and its summary."
      "\n\n"
      "example:\n  kessler show 1 --kappas 0.5,1,10");
  return [o, &global] { return show(*o, global); };
}

}  // namespace kessler::cli
