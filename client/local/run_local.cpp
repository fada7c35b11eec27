// kessler run SCENARIO --local: the scenario run in this process, no daemon. Progress and events go to
// stdout (a table, or one JSON object per line ending with a summary object); checkpoints, when a
// directory is given, are written atomically (temporary file, fsync, rename).
#include <fcntl.h>
#include <unistd.h>

#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>

#include "client/command.hpp"
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

const char* kUsage =
    "usage: kessler run SCENARIO --local [--threads T] [--output json|table] [--checkpoint-dir DIR]\n"
    "                                   [--resume CHECKPOINT] [--datasets DIR]\n"
    "  SCENARIO            a scenario file, YAML or JSON (see deploy/scenarios/)\n"
    "  --local             run in this process (no daemon)\n"
    "  --threads T         OpenMP threads (default: all cores); results are identical for any T\n"
    "  --output FORMAT     table (default) or json: one object per line, the last one the summary\n"
    "  --checkpoint-dir D  write checkpoints into D (checkpoint-<step>.ckpt; the last three are kept)\n"
    "  --resume FILE       continue the scenario's run from a checkpoint it wrote\n"
    "  --datasets DIR      where the bundled datasets live\n"
    "Ctrl-C stops at the next step (after a checkpoint when --checkpoint-dir is given).\n"
    "Exit codes: 0 finished, 1 failed or stopped early, 2 bad usage or scenario.\n";

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

class PrintingSink final : public EventSink {
 public:
  PrintingSink(bool json, UtcEpoch epoch, std::string checkpoint_dir)
      : json_(json), epoch_(epoch), checkpoint_dir_(std::move(checkpoint_dir)) {}

  void on_encounter(std::uint64_t seq, const Encounter& e) override {
    std::cout << (json_ ? encounter_json(seq, e, epoch_) : encounter_row(seq, e, epoch_)) << '\n';
  }
  void on_burn_up(std::uint64_t seq, const BurnUp& b) override {
    std::cout << (json_ ? burn_up_json(seq, b, epoch_) : burn_up_row(seq, b, epoch_)) << '\n';
  }
  void on_progress(std::uint64_t seq, const Progress& p) override {
    if (json_)
      std::cout << progress_json(seq, p) << '\n';
    else
      std::cerr << progress_row(p) << '\n';
    std::cout.flush();
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
      std::cerr << "checkpoint step " << step << " -> " << path.string() << '\n';
  }
  void on_finished(const RunSummary&) override {}
  void on_failed(const std::string& reason) override {
    std::cerr << "kessler run: failed: " << reason << '\n';
  }

 private:
  bool json_;
  UtcEpoch epoch_;
  std::string checkpoint_dir_;
  std::vector<std::filesystem::path> written_;
};

int run_main(int argc, char** argv) {
  std::string scenario_path, output = "table", checkpoint_dir, resume_path;
  bool local = false;
  BuildOptions options;
  for (int i = 1; i < argc; ++i) {
    std::string arg = argv[i];
    auto value = [&](const char* name) -> const char* {
      if (i + 1 >= argc) {
        std::cerr << "kessler run: " << name << " needs a value\n" << kUsage;
        return nullptr;
      }
      return argv[++i];
    };
    if (arg == "--help" || arg == "-h") {
      std::cout << kUsage;
      return kExitOk;
    } else if (arg == "--local") {
      local = true;
    } else if (arg == "--threads") {
      const char* v = value("--threads");
      if (!v) return kExitUsage;
      char* end = nullptr;
      long t = std::strtol(v, &end, 10);
      if (*end || t < 1 || t > 4096) {
        std::cerr << "kessler run: --threads must be a whole number from 1, got '" << v << "'\n";
        return kExitUsage;
      }
      options.threads = static_cast<int>(t);
    } else if (arg == "--output") {
      const char* v = value("--output");
      if (!v) return kExitUsage;
      output = v;
      if (output != "json" && output != "table") {
        std::cerr << "kessler run: --output must be json or table, got '" << output << "'\n";
        return kExitUsage;
      }
    } else if (arg == "--checkpoint-dir") {
      const char* v = value("--checkpoint-dir");
      if (!v) return kExitUsage;
      checkpoint_dir = v;
    } else if (arg == "--resume") {
      const char* v = value("--resume");
      if (!v) return kExitUsage;
      resume_path = v;
    } else if (arg == "--datasets") {
      const char* v = value("--datasets");
      if (!v) return kExitUsage;
      options.datasets_dir = v;
    } else if (!arg.empty() && arg[0] == '-') {
      std::cerr << "kessler run: unknown option '" << arg << "'\n" << kUsage;
      return kExitUsage;
    } else if (scenario_path.empty()) {
      scenario_path = arg;
    } else {
      std::cerr << "kessler run: one scenario only (got '" << scenario_path << "' and '" << arg << "')\n";
      return kExitUsage;
    }
  }
  if (scenario_path.empty()) {
    std::cerr << "kessler run: no scenario file given\n" << kUsage;
    return kExitUsage;
  }
  if (!local) {
    std::cerr
        << "kessler run: add --local to run in this process (use 'kessler submit' to run on kesslerd)\n";
    return kExitUsage;
  }

  v1::Scenario scenario;
  if (auto e = load_scenario_file(scenario_path, scenario)) {
    std::cerr << "kessler run: " << scenario_path << ": " << e->message() << '\n';
    return kExitUsage;
  }
  if (auto e = validate_scenario(scenario)) {
    std::cerr << "kessler run: " << scenario_path << ": " << e->message() << '\n';
    return kExitUsage;
  }
  if (!checkpoint_dir.empty()) {
    std::error_code ec;
    std::filesystem::create_directories(checkpoint_dir, ec);
    if (ec) {
      std::cerr << "kessler run: cannot create --checkpoint-dir '" << checkpoint_dir << "': " << ec.message()
                << '\n';
      return kExitUsage;
    }
  }

  options.checkpoints = !checkpoint_dir.empty();
  FieldError error;
  std::unique_ptr<Simulation> sim;
  if (!resume_path.empty()) {
    std::ifstream in(resume_path, std::ios::binary);
    if (!in) {
      std::cerr << "kessler run: cannot read checkpoint '" << resume_path << "'\n";
      return kExitUsage;
    }
    std::ostringstream bytes;
    bytes << in.rdbuf();
    sim = resume_simulation(scenario, bytes.str(), options, &error);
  } else {
    sim = build_simulation(scenario, options, &error);
  }
  if (!sim) {
    std::cerr << "kessler run: " << scenario_path << ": " << error.message() << '\n';
    return kExitUsage;
  }

  const bool json = output == "json";
  const SimulationConfig config = to_simulation_config(scenario, options.threads);
  PrintingSink sink(json, config.start_epoch, checkpoint_dir);
  RunControl control;
  g_control = &control;
  g_resumable = !checkpoint_dir.empty();
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  if (!json)
    std::cerr << "running " << (scenario.name().empty() ? scenario_path : scenario.name()) << ": "
              << sim->population().size() << " objects, " << sim->total_steps() - sim->step() << " steps of "
              << config.dt_s << " s\n";
  RunSummary summary;
  try {
    summary = sim->run(sink, control);
  } catch (const std::exception&) {
    g_control = nullptr;
    return kExitFailure;
  }
  g_control = nullptr;
  std::signal(SIGINT, SIG_DFL);
  std::signal(SIGTERM, SIG_DFL);
  if (json)
    std::cout << summary_json(summary) << '\n';
  else
    std::cout << summary_table(summary);
  std::cout.flush();
  return summary.cancelled ? kExitFailure : kExitOk;
}

KESSLER_COMMAND(
    "run", 10,
    "run SCENARIO --local [--threads T] [--output json|table] [--checkpoint-dir DIR] [--resume CKPT]",
    "run a scenario in this process and print its events and fingerprint", run_main);

}  // namespace
}  // namespace kessler::cli
