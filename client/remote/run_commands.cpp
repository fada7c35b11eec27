// kessler submit, watch, runs, show, cancel, delete: the run lifecycle against kesslerd.
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <sstream>
#include <thread>

#include "client/command.hpp"
#include "client/remote/cli_support.hpp"
#include "client/remote/remote_client.hpp"
#include "core/scenario/run_builder.hpp"
#include "core/time/epoch.hpp"

namespace kessler::cli {
namespace {

const char* const kServerHelp =
    "  --server HOST:PORT   kesslerd to talk to (default $KESSLER_SERVER, else 127.0.0.1:50051)\n";

bool read_file(const std::string& path, std::string& out) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  std::ostringstream s;
  s << in.rdbuf();
  out = s.str();
  return true;
}

std::string unix_time_text(double unix_s) {
  if (unix_s <= 0) return "-";
  return UtcEpoch::from_calendar(1970, 1, 1, 0, 0, 0.0).plus_seconds(unix_s).to_iso8601(0);
}

std::string percent(const v1::Progress& p) {
  if (p.total_steps() <= 0) return "-";
  char buf[16];
  std::snprintf(buf, sizeof buf, "%.1f%%",
                100.0 * static_cast<double>(p.step()) / static_cast<double>(p.total_steps()));
  return buf;
}

// ---- watching ----

enum class EventsMode { kAll, kNotable, kNone };

struct WatchOptions {
  OutputFormat format = OutputFormat::kTable;
  EventsMode events = EventsMode::kNotable;
  std::uint64_t after_seq = 0;
  double retry_s = 60.0;
};

class ProgressView {
 public:
  explicit ProgressView(std::string start_epoch) : start_epoch_(std::move(start_epoch)), tty_(isatty(2)) {}

  void update(const v1::Progress& p) {
    last_ = p;
    if (tty_) {
      draw();
    } else {
      // Not a terminal: a line every tenth of the run.
      int decile = p.total_steps() > 0 ? static_cast<int>(10 * p.step() / p.total_steps()) : 0;
      if (decile != last_decile_) {
        last_decile_ = decile;
        std::cerr << line() << "\n";
      }
    }
  }
  void print_event(const std::string& text) {
    if (tty_ && drawn_) std::cerr << "\r\033[K" << std::flush;
    std::cout << text << "\n" << std::flush;
    if (tty_ && drawn_) draw();
  }
  void note(const std::string& text) {
    if (tty_ && drawn_) std::cerr << "\r\033[K";
    std::cerr << text << "\n";
    if (tty_ && drawn_) draw();
  }
  void finish() {
    if (tty_ && drawn_) std::cerr << "\n";
    drawn_ = false;
  }
  std::uint64_t conjunctions = 0, collisions = 0, evasions = 0, burn_ups = 0;

 private:
  std::string line() const {
    const v1::Progress& p = last_;
    double fraction =
        p.total_steps() > 0 ? static_cast<double>(p.step()) / static_cast<double>(p.total_steps()) : 0;
    const int filled = std::clamp(static_cast<int>(fraction * 24 + 0.5), 0, 24);
    std::string bar(26, '.');
    bar.front() = '[';
    bar.back() = ']';
    for (int i = 0; i < filled; ++i) bar[static_cast<std::size_t>(i) + 1] = '#';
    char rate[32] = "-";
    if (p.wall_s() > 0) std::snprintf(rate, sizeof rate, "%.0fx", p.sim_time_s() / p.wall_s());
    std::ostringstream s;
    s << bar << " " << percent(p) << "  " << format_sim_time(start_epoch_, p.sim_time_s()) << "  " << rate
      << " real time  left " << format_duration(p.eta_s()) << "  objects " << p.objects_alive() << "  conj "
      << conjunctions << " coll " << collisions << " evas " << evasions << " burn " << burn_ups;
    return s.str();
  }
  void draw() {
    std::cerr << "\r\033[K" << line() << std::flush;
    drawn_ = true;
  }
  std::string start_epoch_;
  bool tty_;
  bool drawn_ = false;
  int last_decile_ = -1;
  v1::Progress last_;
};

std::string event_text(const v1::RunEvent& e, const std::string& start_epoch) {
  char buf[256];
  if (e.has_encounter()) {
    const auto& c = e.encounter();
    std::snprintf(buf, sizeof buf, "#%-8llu %-11s %s  %llu-%llu  d=%.1f m  kappa=%.3f  v=%.2f km/s",
                  static_cast<unsigned long long>(e.seq()), kind_name(c.kind()),
                  format_sim_time(start_epoch, c.tca_s()).c_str(), static_cast<unsigned long long>(c.id1()),
                  static_cast<unsigned long long>(c.id2()), c.miss_distance_m(), c.kappa(),
                  c.relative_speed_m_s() / 1000.0);
  } else {
    const auto& b = e.burn_up();
    std::snprintf(buf, sizeof buf, "#%-8llu %-11s %s  %llu  altitude %.1f km",
                  static_cast<unsigned long long>(e.seq()), "burn-up",
                  format_sim_time(start_epoch, b.time_s()).c_str(), static_cast<unsigned long long>(b.id()),
                  b.altitude_m() / 1000.0);
  }
  return buf;
}

bool is_ended(v1::RunState s) {
  return s == v1::RUN_STATE_SUCCEEDED || s == v1::RUN_STATE_FAILED || s == v1::RUN_STATE_CANCELLED;
}

// Follows the run to its end, reconnecting after lost connections from the last sequence number seen.
int follow_run(RemoteClient& client, std::int64_t run_id, const WatchOptions& options) {
  v1::Run run;
  CallResult r = client.get(run_id, run);
  if (!r.ok) {
    std::cerr << "kessler: " << r.describe() << "\n";
    return r.exit_code();
  }
  const std::string start_epoch = run.scenario().start_epoch();
  const bool json = options.format == OutputFormat::kJson;
  ProgressView view(start_epoch);
  std::uint64_t cursor = options.after_seq;
  auto last_contact = std::chrono::steady_clock::now();
  v1::RunState state = run.state();
  for (;;) {
    v1::WatchRunRequest request;
    request.set_run_id(run_id);
    request.set_after_seq(cursor);
    request.set_no_progress(json && options.events != EventsMode::kAll);
    r = client.watch(request, [&](const v1::RunEvent& e) {
      last_contact = std::chrono::steady_clock::now();
      if (e.seq() > 0) cursor = e.seq();
      if (e.has_state()) {
        state = e.state().state();
        if (!json) view.note("run " + std::to_string(run_id) + ": " + v1::run_state_name(state));
        return true;
      }
      if (json) {
        if (options.events == EventsMode::kAll) std::cout << to_json(e) << "\n";
        return true;
      }
      if (e.has_progress()) {
        view.update(e.progress());
        return true;
      }
      bool notable = false;
      if (e.has_encounter()) {
        switch (e.encounter().kind()) {
          case v1::ENCOUNTER_KIND_COLLISION:
            ++view.collisions;
            ++view.conjunctions;
            notable = true;
            break;
          case v1::ENCOUNTER_KIND_EVASION:
            ++view.evasions;
            break;
          default:
            ++view.conjunctions;
            notable = e.encounter().kappa() <= 1.0;
        }
      } else if (e.has_burn_up()) {
        ++view.burn_ups;
        notable = true;
      }
      if (options.events == EventsMode::kAll || (options.events == EventsMode::kNotable && notable))
        view.print_event(event_text(e, start_epoch));
      return true;
    });
    if (r.ok && is_ended(state)) break;
    if (r.ok) {  // the stream ended before the run did: reconnect as after a lost connection
      r.ok = false;
      r.code = 14;
      r.code_name = "UNAVAILABLE";
      r.message = "the event stream ended before the run";
    }
    if (!r.unavailable() ||
        std::chrono::steady_clock::now() - last_contact > std::chrono::duration<double>(options.retry_s)) {
      view.finish();
      std::cerr << "kessler: " << r.describe() << "\n";
      return r.exit_code();
    }
    view.note("kessler: connection to " + client.address() + " lost; reconnecting after event " +
              std::to_string(cursor));
    std::this_thread::sleep_for(std::chrono::seconds(1));
  }
  view.finish();
  r = client.get(run_id, run);
  if (!r.ok) {
    std::cerr << "kessler: " << r.describe() << "\n";
    return r.exit_code();
  }
  if (json)
    std::cout << summary_json(run) << std::endl;
  else
    std::cout << summary_text(run) << std::flush;
  return run.state() == v1::RUN_STATE_SUCCEEDED ? kExitOk : kExitFailure;
}

bool parse_watch_options(const Options& o, const std::string& command, WatchOptions& w, int& exit) {
  auto format = parse_output(o.get("--output", "table"));
  if (!format) {
    exit = usage_error(command, "--output must be table or json");
    return false;
  }
  w.format = *format;
  std::string events = o.get("--events", w.format == OutputFormat::kJson ? "none" : "notable");
  if (events == "all")
    w.events = EventsMode::kAll;
  else if (events == "notable")
    w.events = EventsMode::kNotable;
  else if (events == "none")
    w.events = EventsMode::kNone;
  else {
    exit = usage_error(command, "--events must be all, notable or none");
    return false;
  }
  if (o.has("--retry-s") && !parse_double(o.get("--retry-s"), w.retry_s)) {
    exit = usage_error(command, "--retry-s needs a number of seconds");
    return false;
  }
  return true;
}

const char* const kWatchOptionsHelp =
    "  --events MODE        events printed as they come: all, notable (collisions, burn-ups,\n"
    "                       conjunctions with kappa <= 1; the default) or none (the default with json)\n"
    "  --retry-s S          keep reconnecting for S seconds when the daemon goes away (default 60)\n"
    "  --output FORMAT      table (default) or json: with json the last line is the run's summary\n"
    "                       object; --events all adds one JSON line per event before it\n";

// ---- submit ----

int submit_main(int argc, char** argv) {
  Options o;
  std::string error;
  if (!o.parse(argc, argv,
               {{"--watch", false},
                {"--catalog", true},
                {"--threads", true},
                {"--events", true},
                {"--retry-s", true}},
               error))
    return usage_error("submit", error);
  if (o.has("--help")) {
    std::cout
        << "usage: kessler submit FILE [--watch] [options]\n\n"
           "Sends the scenario in FILE (YAML or JSON) to kesslerd, which validates it and queues a run.\n"
           "Prints the run's id; with --watch, follows the run live to its end like 'kessler watch'.\n\n"
           "options:\n"
           "  --watch              follow the run to its end; exit 0 when it succeeds, 1 otherwise\n"
           "  --catalog FILE       use FILE's text as the scenario's inline catalog\n"
           "                       (population.catalog.text; TLE or OMM)\n"
           "  --threads N          OpenMP threads of this run (default: the daemon's --threads)\n"
        << kWatchOptionsHelp << kServerHelp
        << "\nexamples:\n"
           "  kessler submit deploy/scenarios/paper-1day.yaml --watch\n"
           "  kessler submit my.yaml --catalog tles.txt --output json\n";
    return kExitOk;
  }
  if (o.positional.size() != 1) return usage_error("submit", "expects one scenario FILE");
  WatchOptions w;
  int exit = 0;
  if (!parse_watch_options(o, "submit", w, exit)) return exit;
  std::string text;
  if (!read_file(o.positional[0], text)) return usage_error("submit", "cannot read " + o.positional[0]);
  v1::SubmitRunRequest request;
  if (o.has("--catalog")) {
    std::string catalog;
    if (!read_file(o.get("--catalog"), catalog))
      return usage_error("submit", "cannot read " + o.get("--catalog"));
    v1::Scenario scenario;
    if (auto e = parse_scenario(text, scenario)) {
      std::cerr << "kessler submit: " << o.positional[0] << ": " << e->message() << "\n";
      return kExitUsage;
    }
    scenario.mutable_population()->mutable_catalog()->set_text(std::move(catalog));
    *request.mutable_scenario() = std::move(scenario);
  } else {
    request.set_scenario_text(text);
  }
  if (o.has("--threads")) {
    std::uint64_t threads = 0;
    if (!parse_uint(o.get("--threads"), threads) || threads > 1024)
      return usage_error("submit", "--threads needs an integer 0..1024");
    request.set_threads(static_cast<int>(threads));
  }
  RemoteClient client(server_address(o.get("--server")));
  v1::Run run;
  CallResult r = client.submit(request, run);
  if (!r.ok) {
    std::cerr << "kessler submit: " << o.positional[0] << ": " << r.describe() << "\n";
    return r.exit_code();
  }
  if (!o.has("--watch")) {
    if (w.format == OutputFormat::kJson)
      std::cout << JsonObject()
                       .add("run_id", static_cast<std::int64_t>(run.id()))
                       .add("state", v1::run_state_name(run.state()))
                       .str()
                << "\n";
    else
      std::cout << "run " << run.id() << " " << v1::run_state_name(run.state())
                << (run.queue_position() > 0 ? " (position " + std::to_string(run.queue_position()) + ")"
                                             : "")
                << "\n";
    return kExitOk;
  }
  if (w.format != OutputFormat::kJson) std::cerr << "run " << run.id() << " submitted\n";
  return follow_run(client, run.id(), w);
}

// ---- watch ----

int watch_main(int argc, char** argv) {
  Options o;
  std::string error;
  if (!o.parse(argc, argv, {{"--after", true}, {"--events", true}, {"--retry-s", true}}, error))
    return usage_error("watch", error);
  if (o.has("--help")) {
    std::cout
        << "usage: kessler watch RUN [options]\n\n"
           "Follows a run live: a progress bar (simulated time, rate, time left, counts) and its events as\n"
           "they come, then its summary. A finished run is replayed from the store. Exit 0 when the run\n"
           "succeeded, 1 otherwise.\n\n"
           "options:\n"
           "  --after SEQ          only events after sequence number SEQ (resume where you left off)\n"
        << kWatchOptionsHelp << kServerHelp << "\nexample:\n  kessler watch 3 --events all\n";
    return kExitOk;
  }
  std::int64_t run_id = 0;
  if (o.positional.size() != 1 || !parse_run_id(o.positional[0], run_id))
    return usage_error("watch", "expects one RUN id");
  WatchOptions w;
  int exit = 0;
  if (!parse_watch_options(o, "watch", w, exit)) return exit;
  if (o.has("--after") && !parse_uint(o.get("--after"), w.after_seq))
    return usage_error("watch", "--after needs a sequence number");
  RemoteClient client(server_address(o.get("--server")));
  return follow_run(client, run_id, w);
}

// ---- runs ----

int runs_main(int argc, char** argv) {
  Options o;
  std::string error;
  if (!o.parse(argc, argv, {{"--state", true}, {"--limit", true}}, error)) return usage_error("runs", error);
  if (o.has("--help")) {
    std::cout << "usage: kessler runs [--state STATES] [--limit N] [--output table|csv|json]\n\n"
                 "Lists runs, newest first.\n\n"
                 "options:\n"
                 "  --state STATES       only these states, comma-separated: queued, running, succeeded,\n"
                 "                       failed, cancelled\n"
                 "  --limit N            at most N runs (default 50)\n"
                 "  --output FORMAT      table (default), csv or json (an array of runs)\n"
              << kServerHelp << "\nexample:\n  kessler runs --state running,queued\n";
    return kExitOk;
  }
  if (!o.positional.empty()) return usage_error("runs", "takes no arguments");
  auto format = parse_output(o.get("--output", "table"));
  if (!format) return usage_error("runs", "--output must be table, csv or json");
  v1::ListRunsRequest request;
  std::stringstream states(o.get("--state"));
  for (std::string s; std::getline(states, s, ',');) {
    if (s.empty()) continue;
    v1::RunState state = v1::RUN_STATE_UNSPECIFIED;
    for (int v = 1; v <= 5; ++v)
      if (s == v1::run_state_name(static_cast<v1::RunState>(v))) state = static_cast<v1::RunState>(v);
    if (state == v1::RUN_STATE_UNSPECIFIED) return usage_error("runs", "unknown state '" + s + "'");
    request.add_states(state);
  }
  std::uint64_t limit = 50;
  if (o.has("--limit") && (!parse_uint(o.get("--limit"), limit) || limit == 0))
    return usage_error("runs", "--limit needs a positive integer");
  RemoteClient client(server_address(o.get("--server")));
  std::vector<v1::Run> runs;
  while (runs.size() < limit) {
    request.set_page_size(static_cast<int>(std::min<std::uint64_t>(limit - runs.size(), 1000)));
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
  if (*format == OutputFormat::kJson) {
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
    return kExitOk;
  }
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
  if (*format == OutputFormat::kCsv) {
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
  return kExitOk;
}

// ---- show ----

int show_main(int argc, char** argv) {
  Options o;
  std::string error;
  if (!o.parse(argc, argv, {{"--kappas", true}, {"--bin-s", true}}, error)) return usage_error("show", error);
  if (o.has("--help")) {
    std::cout << "usage: kessler show RUN [--output table|json]\n\n"
                 "Shows a run: its scenario, state, times, phase timers, conjunction counts by kappa over\n"
                 "time and its summary.\n\n"
                 "options:\n"
                 "  --kappas LIST        kappa thresholds to count at, comma-separated (default 1,2,5,10)\n"
                 "  --bin-s S            width of a time bin in seconds (default: the run's length / 24)\n"
                 "  --output FORMAT      table (default) or json: one line with the run and its stats, then\n"
                 "                       the run's summary object (the same keys as 'run --local') last\n"
              << kServerHelp << "\nexample:\n  kessler show 1 --kappas 0.5,1,10\n";
    return kExitOk;
  }
  std::int64_t run_id = 0;
  if (o.positional.size() != 1 || !parse_run_id(o.positional[0], run_id))
    return usage_error("show", "expects one RUN id");
  auto format = parse_output(o.get("--output", "table"));
  if (!format || *format == OutputFormat::kCsv) return usage_error("show", "--output must be table or json");
  v1::GetRunStatsRequest stats_request;
  stats_request.set_run_id(run_id);
  std::stringstream kappas(o.get("--kappas"));
  for (std::string k; std::getline(kappas, k, ',');) {
    double v = 0;
    if (!parse_double(k, v) || v <= 0) return usage_error("show", "--kappas needs positive numbers");
    stats_request.add_kappas(v);
  }
  if (o.has("--bin-s")) {
    double bin = 0;
    if (!parse_double(o.get("--bin-s"), bin) || bin <= 0)
      return usage_error("show", "--bin-s needs a positive number");
    stats_request.set_time_bin_s(bin);
  }
  RemoteClient client(server_address(o.get("--server")));
  v1::Run run;
  v1::RunStats stats;
  CallResult r = client.get(run_id, run);
  if (r.ok) r = client.stats(stats_request, stats);
  if (!r.ok) {
    std::cerr << "kessler show: " << r.describe() << "\n";
    return r.exit_code();
  }
  // An inline catalog can be megabytes: show its size, not its text.
  std::string catalog_note;
  if (run.scenario().population().has_catalog()) {
    auto* catalog = run.mutable_scenario()->mutable_population()->mutable_catalog();
    catalog_note = std::to_string(catalog->text().size()) + " bytes inline";
    catalog->set_text("<" + catalog_note + ">");
  }
  if (*format == OutputFormat::kJson) {
    std::cout << JsonObject().add_raw("run", to_json(run)).add_raw("stats", to_json(stats)).str() << "\n";
    std::cout << summary_json(run) << std::endl;
    return kExitOk;
  }
  std::cout << "run " << run.id() << (run.name().empty() ? "" : " (" + run.name() + ")") << ": "
            << v1::run_state_name(run.state()) << "\n";
  if (!run.error().empty()) std::cout << "  error     " << run.error() << "\n";
  std::cout << "  created   " << unix_time_text(run.created_unix_s()) << "\n"
            << "  started   " << unix_time_text(run.started_unix_s()) << "\n"
            << "  finished  " << unix_time_text(run.finished_unix_s()) << "\n"
            << "  threads   " << (run.threads() ? std::to_string(run.threads()) : "daemon default") << "\n";
  if (run.has_progress())
    std::cout << "  progress  " << percent(run.progress()) << " (step " << run.progress().step() << " of "
              << run.progress().total_steps() << "), last event " << run.last_seq() << "\n";
  std::cout << "\nscenario\n  " << to_json(run.scenario()) << "\n";
  if (run.has_summary()) {
    const auto& t = run.summary().timers();
    std::cout << "\ntimers\n"
              << render_table({"  PHASE", "SECONDS", "SHARE"}, [&] {
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
                   return rows;
                 }());
  }
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
            << " collisions, " << stats.evasions() << " evasions, " << stats.burn_ups() << " burn-ups\n\n";
  std::cout << summary_text(run);
  return kExitOk;
}

// ---- cancel, delete ----

int cancel_main(int argc, char** argv) {
  Options o;
  std::string error;
  if (!o.parse(argc, argv, {}, error)) return usage_error("cancel", error);
  if (o.has("--help")) {
    std::cout << "usage: kessler cancel RUN [--output table|json]\n\n"
                 "Cancels a run: a queued run at once, a running one at the end of its current step. Its\n"
                 "events so far stay queryable.\n\noptions:\n"
              << kServerHelp;
    return kExitOk;
  }
  std::int64_t run_id = 0;
  if (o.positional.size() != 1 || !parse_run_id(o.positional[0], run_id))
    return usage_error("cancel", "expects one RUN id");
  auto format = parse_output(o.get("--output", "table"));
  if (!format) return usage_error("cancel", "--output must be table or json");
  RemoteClient client(server_address(o.get("--server")));
  v1::Run run;
  CallResult r = client.cancel(run_id, run);
  if (!r.ok) {
    std::cerr << "kessler cancel: " << r.describe() << "\n";
    return r.exit_code();
  }
  if (*format == OutputFormat::kJson)
    std::cout << JsonObject().add("run_id", run_id).add("state", v1::run_state_name(run.state())).str()
              << "\n";
  else if (run.state() == v1::RUN_STATE_CANCELLED)
    std::cout << "run " << run_id << " cancelled\n";
  else
    std::cout << "run " << run_id << " cancelling at the end of its current step\n";
  return kExitOk;
}

int delete_main(int argc, char** argv) {
  Options o;
  std::string error;
  if (!o.parse(argc, argv, {}, error)) return usage_error("delete", error);
  if (o.has("--help")) {
    std::cout << "usage: kessler delete RUN [--output table|json]\n\n"
                 "Deletes an ended run with its events, conjunctions and checkpoints. Cancel a running run\n"
                 "first.\n\noptions:\n"
              << kServerHelp;
    return kExitOk;
  }
  std::int64_t run_id = 0;
  if (o.positional.size() != 1 || !parse_run_id(o.positional[0], run_id))
    return usage_error("delete", "expects one RUN id");
  auto format = parse_output(o.get("--output", "table"));
  if (!format) return usage_error("delete", "--output must be table or json");
  RemoteClient client(server_address(o.get("--server")));
  CallResult r = client.remove(run_id);
  if (!r.ok) {
    std::cerr << "kessler delete: " << r.describe() << "\n";
    return r.exit_code();
  }
  if (*format == OutputFormat::kJson)
    std::cout << JsonObject().add("run_id", run_id).add("deleted", true).str() << "\n";
  else
    std::cout << "run " << run_id << " deleted\n";
  return kExitOk;
}

}  // namespace

KESSLER_COMMAND("submit", 20, "submit FILE [--watch]",
                "queue a run of a scenario on kesslerd (and follow it)", submit_main);
KESSLER_COMMAND("watch", 21, "watch RUN", "follow a run live: progress, events, summary", watch_main);
KESSLER_COMMAND("runs", 22, "runs [--state S]", "list runs", runs_main);
KESSLER_COMMAND("show", 23, "show RUN", "a run's scenario, state, timers and conjunction counts by kappa",
                show_main);
KESSLER_COMMAND("cancel", 25, "cancel RUN", "cancel a queued or running run", cancel_main);
KESSLER_COMMAND("delete", 26, "delete RUN", "delete an ended run and everything stored for it", delete_main);

}  // namespace kessler::cli
