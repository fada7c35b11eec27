// kessler run SCENARIO --local: the scenario run in this process, no daemon. A catalog's ingest report,
// then events go to stdout (a table, or one JSON object per line ending with a summary object);
// checkpoints, when a directory is given, are written atomically (temporary file, fsync, rename).
// Shared by `kessler run --local` and kessler-mpi (whose ranks each run it; rank 0 alone prints).
#include <fcntl.h>
#include <unistd.h>

#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <unordered_map>

#include "client/commands/local_run.hpp"
#include "client/render.hpp"
#include "core/scenario/run_builder.hpp"

namespace kessler::cli {
namespace {

RunControl* g_control = nullptr;
bool g_resumable = false;

extern "C" void on_signal(int) {
  if (!g_control) return;
  // First signal: stop at the next step boundary (after a checkpoint when there is a directory for it);
  // a second one just cancels.
  if (g_resumable && !g_control->stop_after_checkpoint.load())
    g_control->stop_after_checkpoint = true;
  else
    g_control->cancel = true;
}

bool write_atomically(const std::filesystem::path& path, const std::string& bytes, std::string& error) {
  const std::filesystem::path tmp = path.string() + ".tmp";
  int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  if (fd < 0) {
    error = std::string("cannot write ") + tmp.string() + ": " + std::strerror(errno);
    return false;
  }
  std::size_t done = 0;
  while (done < bytes.size()) {
    ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0) {
      if (errno == EINTR) continue;
      error = std::string("cannot write ") + tmp.string() + ": " + std::strerror(errno);
      ::close(fd);
      return false;
    }
    done += static_cast<std::size_t>(n);
  }
  if (::fsync(fd) != 0 || ::close(fd) != 0) {
    error = std::string("cannot flush ") + tmp.string() + ": " + std::strerror(errno);
    return false;
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    error = "cannot rename " + tmp.string() + ": " + ec.message();
    return false;
  }
  return true;
}

// Table output in a terminal: the progress line is redrawn in place on stderr, and taken off the
// screen while other lines are printed. Not a terminal: a log of progress lines.
class PrintingSink final : public EventSink {
 public:
  PrintingSink(bool json, UtcEpoch epoch, std::string checkpoint_dir, std::string program)
      : json_(json),
        tty_(!json && isatty(2)),
        epoch_(epoch),
        checkpoint_dir_(std::move(checkpoint_dir)),
        program_(std::move(program)) {}

  // The names of the run's objects by id, for the encounter lines.
  void set_names(const Population& population) {
    for (std::size_t i = 0; i < population.size(); ++i)
      if (!population.name[i].empty()) names_[population.id[i]] = population.name[i];
  }

  void on_encounter(std::uint64_t seq, const Encounter& e) override {
    const EncounterNames names{name_of(e.id1), name_of(e.id2)};
    print(std::cout, json_ ? encounter_json(seq, e, epoch_, names) : encounter_row(seq, e, epoch_, names));
  }
  void on_burn_up(std::uint64_t seq, const BurnUp& b) override {
    print(std::cout, json_ ? burn_up_json(seq, b, epoch_) : burn_up_row(seq, b, epoch_));
  }
  void on_breakup(std::uint64_t seq, const BreakupReport& b) override {
    print(std::cout, json_ ? breakup_json(seq, b, epoch_) : breakup_row(seq, b, epoch_));
  }
  void on_lifecycle(std::uint64_t seq, const LifecycleReport& l) override {
    print(std::cout, json_ ? lifecycle_json(seq, l, epoch_) : lifecycle_row(seq, l, epoch_));
  }
  void on_progress(std::uint64_t seq, const Progress& p) override {
    if (json_) {
      std::cout << progress_json(seq, p) << '\n';
    } else if (tty_) {
      std::cout.flush();
      progress_ = progress_row(p);
      std::cerr << "\r\033[K" << progress_ << std::flush;
    } else {
      std::cerr << progress_row(p) << '\n';
    }
    std::cout.flush();
  }
  // Ends the progress line so what follows starts on a line of its own.
  void finish() {
    if (!progress_.empty()) std::cerr << '\n';
    progress_.clear();
  }
  void on_checkpoint(std::uint64_t last_seq, std::int64_t step, const std::string& bytes) override {
    if (checkpoint_dir_.empty()) return;
    std::cout.flush();  // the events up to last_seq are out before the checkpoint that covers them
    const auto path =
        std::filesystem::path(checkpoint_dir_) / ("checkpoint-" + std::to_string(step) + ".ckpt");
    std::string error;
    if (!write_atomically(path, bytes, error)) throw std::runtime_error(error);
    written_.push_back(path);
    while (written_.size() > 3) {
      std::error_code ec;
      std::filesystem::remove(written_.front(), ec);
      written_.erase(written_.begin());
    }
    if (json_)
      std::cout << checkpoint_json(last_seq, step, path.string()) << '\n';
    else
      print(std::cerr, "checkpoint step " + std::to_string(step) + " -> " + path.string());
  }
  void on_finished(const RunSummary&) override { finish(); }
  void on_failed(const std::string& reason) override {
    finish();
    std::cerr << program_ << ": failed: " << reason << '\n';
  }

 private:
  void print(std::ostream& out, const std::string& line) {
    if (!progress_.empty()) std::cerr << "\r\033[K" << std::flush;
    out << line << '\n';
    if (!progress_.empty()) {
      out.flush();
      std::cerr << progress_ << std::flush;
    }
  }

  std::string name_of(ObjectId id) const {
    auto it = names_.find(id);
    return object_name(id, it == names_.end() ? std::string() : it->second);
  }

  bool json_;
  bool tty_;
  std::unordered_map<ObjectId, std::string> names_;
  std::string progress_;  // the progress line on the screen, when there is one
  UtcEpoch epoch_;
  std::string checkpoint_dir_;
  std::string program_;
  std::vector<std::filesystem::path> written_;
};

// The scenario read and checked, the checkpoint directory made: nullopt, else the exit code.
std::optional<int> prepare(const LocalRunOptions& o, v1::Scenario& scenario) {
  if (!o.local) {
    std::cerr << o.program
              << ": add --local to run in this process (use 'kessler submit' to run on kesslerd)\n";
    return kExitUsage;
  }
  if (o.scenario) {
    scenario = *o.scenario;
  } else if (o.scenario_binary) {
    std::ifstream in(o.scenario_path, std::ios::binary);
    if (!in || !scenario.ParseFromIstream(&in)) {
      std::cerr << o.program << ": " << o.scenario_path << ": not a serialized kessler.v1.Scenario\n";
      return kExitUsage;
    }
  } else if (auto e = load_scenario_file(o.scenario_path, scenario)) {
    std::cerr << o.program << ": " << o.scenario_path << ": " << e->message() << '\n';
    return kExitUsage;
  }
  if (auto e = validate_scenario(scenario)) {
    std::cerr << o.program << ": " << o.scenario_path << ": " << e->message() << '\n';
    return kExitUsage;
  }
  if (!o.checkpoint_dir.empty()) {
    std::error_code ec;
    std::filesystem::create_directories(o.checkpoint_dir, ec);
    if (ec) {
      std::cerr << o.program << ": cannot create --checkpoint-dir '" << o.checkpoint_dir
                << "': " << ec.message() << '\n';
      return kExitUsage;
    }
  }
  return std::nullopt;
}

// A fresh run, or one resumed from a checkpoint (which has no ingest to report). nullptr after an error
// is printed.
std::unique_ptr<Simulation> build(const LocalRunOptions& o, const v1::Scenario& scenario,
                                  std::optional<IngestReport>& ingest) {
  BuildOptions options = o.build;
  options.checkpoints = !o.checkpoint_dir.empty() || o.sink_checkpoints;
  if (!o.sink) {
    // Population snapshots are for a daemon's store: nothing here prints them, and each is a pass over
    // the whole population. They never change a result (nor the configuration key a checkpoint carries).
    options.adjust_config = [adjust = options.adjust_config](SimulationConfig& config) {
      if (adjust) adjust(config);
      config.snapshot_every_steps = 0;
    };
  }
  FieldError error;
  std::unique_ptr<Simulation> sim;
  if (!o.resume_path.empty()) {
    std::ifstream in(o.resume_path, std::ios::binary);
    if (!in) {
      std::cerr << o.program << ": cannot read checkpoint '" << o.resume_path << "'\n";
      return nullptr;
    }
    std::ostringstream bytes;
    bytes << in.rdbuf();
    sim = resume_simulation(scenario, bytes.str(), options, &error);
  } else {
    sim = build_simulation(scenario, options, &error, &ingest);
  }
  if (!sim) std::cerr << o.program << ": " << o.scenario_path << ": " << error.message() << '\n';
  return sim;
}

}  // namespace

int run_local(const LocalRunOptions& o, OutputFormat format) {
  v1::Scenario scenario;
  if (auto exit = prepare(o, scenario)) return *exit;
  const bool json = format == OutputFormat::kJson;
  std::optional<IngestReport> ingest;
  std::unique_ptr<Simulation> sim = build(o, scenario, ingest);
  // What the ingest did comes first, also when it left nothing to run.
  const bool prints = o.prints && !o.sink;
  if (ingest && prints)
    std::cout << (json ? ingest_json(ingest_outcome(*ingest)) + "\n" : ingest_table(ingest_outcome(*ingest)));
  std::cout.flush();
  if (!sim) return kExitUsage;
  if (o.check_built) {
    if (auto problem = o.check_built(*sim)) {
      std::cerr << o.program << ": " << o.scenario_path << ": " << *problem << '\n';
      return kExitUsage;
    }
  }

  const SimulationConfig config = to_simulation_config(scenario, o.build.threads);
  PrintingSink printing(json, config.start_epoch, o.checkpoint_dir, o.program);
  NullSink silent;
  EventSink& sink = o.sink && o.prints ? *o.sink : prints ? static_cast<EventSink&>(printing) : silent;
  if (prints) printing.set_names(sim->population());
  RunControl control;
  // A host that sees the controls handles the signals itself (kessler-mpi: every rank must stop at the
  // same step).
  const bool own_signals = !o.on_control;
  if (own_signals) {
    g_control = &control;
    g_resumable = !o.checkpoint_dir.empty();
    std::signal(SIGINT, on_signal);
    std::signal(SIGTERM, on_signal);
  } else {
    o.on_control(&control);
  }
  auto release_control = [&] {
    if (own_signals) {
      g_control = nullptr;
      std::signal(SIGINT, SIG_DFL);
      std::signal(SIGTERM, SIG_DFL);
    } else {
      o.on_control(nullptr);
    }
  };
  if (!json && prints)
    std::cerr << "running " << (scenario.name().empty() ? o.scenario_path : scenario.name()) << ": "
              << sim->population().size() << " objects, " << sim->total_steps() - sim->step() << " steps of "
              << config.dt_s << " s\n";
  RunSummary summary;
  try {
    summary = sim->run(sink, control);
  } catch (const std::exception&) {
    release_control();
    return kExitFailure;
  }
  release_control();
  if (o.prints && o.on_summary) o.on_summary(summary);
  if (prints) {
    printing.finish();
    if (json)
      std::cout << summary_json(summary) << '\n';
    else
      std::cout << summary_table(summary);
    std::cout.flush();
  }
  return summary.cancelled ? kExitFailure : kExitOk;
}

}  // namespace kessler::cli
