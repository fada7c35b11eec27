#include "client/commands/follow.hpp"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <iostream>
#include <memory>
#include <sstream>
#include <thread>

#include "client/remote/cli_support.hpp"
#include "client/render.hpp"

namespace kessler::cli {

const char* const kWatchOutputHelp =
    "table (default) or json: with json the first line is the ingest report (for catalogs), the last the "
    "run's summary object; --events all adds one JSON line per event between them";

void add_watch_options(CLI::App& command, WatchOptions& options) {
  command
      .add_option("--events", options.events,
                  "events printed as they come: all, notable (collisions, burn-ups, breakups, launches, "
                  "conjunctions with kappa <= 1; the default) or none (the default with json)")
      ->option_text("MODE")
      ->check(CLI::IsMember({"all", "notable", "none"}));
  command
      .add_option("--retry-s", options.retry_s,
                  "keep reconnecting for S seconds when the daemon goes away (default 60)")
      ->option_text("S")
      ->check(CLI::Validator(
          [](std::string& text) {
            double v = 0;
            return CLI::detail::lexical_cast(text, v) && v >= 0.0 && v <= 1e9
                       ? std::string()
                       : "must be a number of seconds from 0 to 1e9, got " + text.substr(0, 20);
          },
          "S", "seconds"));
}

namespace {

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
  std::uint64_t conjunctions = 0, collisions = 0, evasions = 0, burn_ups = 0, breakups = 0, launched = 0;

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
    s << bar << " " << progress_percent(p) << "  " << format_sim_time(start_epoch_, p.sim_time_s()) << "  "
      << rate << " real time  left " << format_duration(p.eta_s()) << "  objects " << p.objects_alive()
      << "  conj " << conjunctions << " coll " << collisions << " evas " << evasions << " burn " << burn_ups;
    if (breakups > 0) s << " brk " << breakups;
    if (launched > 0) s << " launched " << launched;
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

// "25544 (ISS (ZARYA))", "1000000007 (FRAGMENT 1000000007)", or the id alone where the population has
// no name.
std::string object_text(std::uint64_t id, const std::string& name) {
  const std::string shown = object_name(id, name);
  return shown.empty() ? std::to_string(id) : std::to_string(id) + " (" + shown + ")";
}

UtcEpoch epoch_of(const std::string& start_epoch) {
  auto epoch = UtcEpoch::parse_iso8601(start_epoch.empty() ? "2022-01-01T00:00:00Z" : start_epoch);
  return epoch ? *epoch : UtcEpoch::from_calendar(2022, 1, 1, 0, 0, 0.0);
}

// "#12  launch  2022-01-01 00:30:00  60 objects (2000000000-2000000059), plan row 0", or an object's
// end of life, disposal (with its altitude), failed disposal or de-orbit.
std::string lifecycle_text(const v1::RunEvent& e, const std::string& start_epoch) {
  const LifecycleReport l = lifecycle_report_of(e.lifecycle());
  const std::string first = std::to_string(l.first_id), last = std::to_string(l.last_id);
  std::string what = first;
  char buf[256];
  if (l.kind == LifecycleEventKind::kLaunch)
    what = std::to_string(l.last_id - l.first_id + 1) + " objects (" + first + "-" + last + "), plan row " +
           std::to_string(l.row);
  if (l.kind == LifecycleEventKind::kDisposal) {
    std::snprintf(buf, sizeof buf, "  altitude %.1f km", l.altitude_m / 1e3);
    what += buf;
  }
  std::snprintf(buf, sizeof buf, "#%-8llu %-11s %s  %s", static_cast<unsigned long long>(e.seq()),
                lifecycle_kind_name(l.kind), format_sim_time(start_epoch, l.time_s).c_str(), what.c_str());
  return buf;
}

std::string event_text(const v1::RunEvent& e, const std::string& start_epoch) {
  char buf[384];
  if (e.has_lifecycle()) return lifecycle_text(e, start_epoch);
  if (e.has_breakup()) {
    const BreakupReport b = breakup_report_of(e.breakup());
    std::string parents;
    for (ObjectId id : b.parents) {
      if (!parents.empty()) parents += " + ";
      parents += std::to_string(id);
    }
    std::snprintf(buf, sizeof buf, "#%-8llu %-11s %s  #%u %s of %s  %llu fragments (%llu-%llu)  %.1f kg%s",
                  static_cast<unsigned long long>(e.seq()), "breakup",
                  format_sim_time(start_epoch, b.time_s).c_str(), static_cast<unsigned>(b.breakup_id),
                  breakup_kind_name(b.kind), parents.c_str(),
                  static_cast<unsigned long long>(b.fragment_count),
                  static_cast<unsigned long long>(b.first_id), static_cast<unsigned long long>(b.last_id),
                  b.fragment_mass_kg, b.catastrophic ? "  catastrophic" : "");
  } else if (e.has_encounter()) {
    const auto& c = e.encounter();
    std::snprintf(buf, sizeof buf, "#%-8llu %-11s %s  %s - %s  d=%.1f m  kappa=%.3f  v=%.2f km/s",
                  static_cast<unsigned long long>(e.seq()), kind_name(c.kind()),
                  format_sim_time(start_epoch, c.tca_s()).c_str(), object_text(c.id1(), c.name1()).c_str(),
                  object_text(c.id2(), c.name2()).c_str(), c.miss_distance_m(), c.kappa(),
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

// One run followed to its end: the stream's events rendered, reconnecting after lost connections from
// the last sequence number seen.
class Follower {
 public:
  Follower(RemoteClient& client, std::int64_t run_id, const WatchOptions& options, OutputFormat format)
      : client_(client),
        run_id_(run_id),
        json_(format == OutputFormat::kJson),
        cursor_(options.after_seq),
        retry_s_(options.retry_s) {
    const std::string events = options.events.empty() ? (json_ ? "none" : "notable") : options.events;
    events_ = events == "all"    ? EventsMode::kAll
              : events == "none" ? EventsMode::kNone
                                 : EventsMode::kNotable;
  }

  int run() {
    v1::Run run;
    CallResult r = client_.get(run_id_, run);
    if (!r.ok) return fail(r);
    start_epoch_ = run.scenario().start_epoch();
    view_ = std::make_unique<ProgressView>(start_epoch_);
    state_ = run.state();
    show_ingest(run);
    if (int exit = stream(); exit >= 0) return exit;
    view_->finish();
    r = client_.get(run_id_, run);
    if (!r.ok) return fail(r);
    show_ingest(run);
    ingest_done_ = true;
    if (json_)
      std::cout << summary_json(run) << std::endl;
    else
      std::cout << summary_text(run) << std::flush;
    return run.state() == v1::RUN_STATE_SUCCEEDED ? kExitOk : kExitFailure;
  }

 private:
  enum class EventsMode { kAll, kNotable, kNone };

  int fail(const CallResult& r) {
    if (view_) view_->finish();
    std::cerr << "kessler: " << r.describe() << "\n";
    return r.exit_code();
  }

  // The ingest report, once, before anything else is printed; known from when the population is built.
  void show_ingest(const v1::Run& run) {
    if (ingest_done_ || !run.has_ingest()) return;
    ingest_done_ = true;
    const IngestOutcome ingest = ingest_outcome_of(run.ingest());
    if (json_) {
      std::cout << ingest_json(ingest) << "\n" << std::flush;
    } else {
      std::string text = ingest_table(ingest);
      text.pop_back();
      view_->print_event(text);
    }
  }
  void refresh_ingest() {
    if (ingest_done_) return;
    v1::Run run;
    if (client_.get(run_id_, run).ok) show_ingest(run);
    ingest_done_ = true;  // not from a catalog: nothing to show
  }

  // -1 once the run has ended, else the exit code of a failure.
  int stream() {
    auto last_contact = std::chrono::steady_clock::now();
    for (;;) {
      v1::WatchRunRequest request;
      request.set_run_id(run_id_);
      request.set_after_seq(cursor_);
      request.set_no_progress(json_ && events_ != EventsMode::kAll);
      CallResult r = client_.watch(request, [&](const v1::RunEvent& e) {
        last_contact = std::chrono::steady_clock::now();
        on_event(e);
        return true;
      });
      if (r.ok && is_ended(state_)) return -1;
      if (r.ok) {  // the stream ended before the run did: reconnect as after a lost connection
        r.ok = false;
        r.code = 14;
        r.code_name = "UNAVAILABLE";
        r.message = "the event stream ended before the run";
      }
      if (!r.unavailable() ||
          std::chrono::steady_clock::now() - last_contact > std::chrono::duration<double>(retry_s_))
        return fail(r);
      view_->note("kessler: connection to " + client_.address() + " lost; reconnecting after event " +
                  std::to_string(cursor_));
      std::this_thread::sleep_for(std::chrono::seconds(1));
    }
  }

  void on_event(const v1::RunEvent& e) {
    if (e.seq() > 0) cursor_ = e.seq();
    if (e.has_state()) {
      state_ = e.state().state();
      if (!json_) view_->note("run " + std::to_string(run_id_) + ": " + v1::run_state_name(state_));
      return;
    }
    refresh_ingest();  // the population is built before the run's first event
    if (json_) {
      if (events_ == EventsMode::kAll)
        std::cout << (e.has_breakup()
                          ? breakup_json(e.seq(), breakup_report_of(e.breakup()), epoch_of(start_epoch_))
                      : e.has_lifecycle() ? lifecycle_json(e.seq(), lifecycle_report_of(e.lifecycle()),
                                                           epoch_of(start_epoch_))
                                          : to_json(e))
                  << "\n";
      return;
    }
    if (e.has_progress()) {
      view_->update(e.progress());
      return;
    }
    const bool notable = count(e);
    if (events_ == EventsMode::kAll || (events_ == EventsMode::kNotable && notable))
      view_->print_event(event_text(e, start_epoch_));
  }

  // Counts the event in the progress line; true when it is notable.
  bool count(const v1::RunEvent& e) {
    if (e.has_lifecycle()) {
      // Launches are notable; ends of life and disposals (one per launched payload) only with "all".
      if (e.lifecycle().kind() != v1::LIFECYCLE_KIND_LAUNCH) return false;
      view_->launched += e.lifecycle().last_id() - e.lifecycle().first_id() + 1;
      return true;
    }
    if (e.has_breakup()) {
      ++view_->breakups;
      return true;
    }
    if (e.has_burn_up()) {
      ++view_->burn_ups;
      return true;
    }
    if (!e.has_encounter()) return false;
    switch (e.encounter().kind()) {
      case v1::ENCOUNTER_KIND_COLLISION:
        ++view_->collisions;
        ++view_->conjunctions;
        return true;
      case v1::ENCOUNTER_KIND_EVASION:
        ++view_->evasions;
        return false;
      default:
        ++view_->conjunctions;
        return e.encounter().kappa() <= 1.0;
    }
  }

  RemoteClient& client_;
  std::int64_t run_id_;
  bool json_;
  std::uint64_t cursor_;
  double retry_s_;
  EventsMode events_ = EventsMode::kNotable;
  std::string start_epoch_;
  std::unique_ptr<ProgressView> view_;
  v1::RunState state_ = v1::RUN_STATE_UNSPECIFIED;
  bool ingest_done_ = false;
};

}  // namespace

int follow_run(RemoteClient& client, std::int64_t run_id, const WatchOptions& options, OutputFormat format) {
  return Follower(client, run_id, options, format).run();
}

}  // namespace kessler::cli
