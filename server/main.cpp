// kesslerd: the Kessler daemon. Hosts simulation runs behind a gRPC API and keeps them in SQLite.
#include <signal.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>

#include "server/api_server.hpp"
#include "server/run_manager.hpp"

namespace {

const char* const kUsage = R"(kesslerd - the Kessler simulation daemon

usage: kesslerd [options]

Accepts scenario runs over gRPC (kessler.v1.KesslerService, with the standard health service and
server reflection), runs them in order, streams their events and keeps runs, events, conjunctions and
checkpoints in a SQLite database. Runs left running by a crash resume from their last checkpoint at
start; SIGTERM or SIGINT checkpoints running runs and exits cleanly.

options:
  --listen HOST:PORT    address to serve on (default 127.0.0.1:50051; port 0 picks a free one)
  --db PATH             SQLite database, created when missing, private to the user (default
                        var/kessler.db)
  --runs-at-once N      runs simulated at the same time; the rest queue in order (default 1)
  --threads N           OpenMP threads per run unless a submission asks otherwise (default 0: all cores)
  --queue-limit N       queued runs accepted before SubmitRun answers RESOURCE_EXHAUSTED (default 1000)
  --max-ensemble-members N
                        most members SubmitEnsemble takes; more is INVALID_ARGUMENT (default 1000)
  --max-message-mb N    largest request accepted, e.g. a scenario with an inline catalog (default 64)
  --datasets DIR        bundled datasets (default: the build's deploy/datasets)
  --traffic-plans DIR   shipped launch plans, a scenario's traffic.plans (default: the build's
                        deploy/traffic)
  --checkpoint-write-ms N
                        write a run's checkpoints to the database at most every N ms; a newer one
                        replaces one still waiting (default 1000; 0: every checkpoint as it comes)
  --port-file PATH      write the port listened on to PATH once serving (for scripts and tests)
  --help                this text
)";

int usage_error(const std::string& message) {
  std::cerr << "kesslerd: " << message << " (see kesslerd --help)\n";
  return 2;
}

bool parse_int(const std::string& text, long min, long max, long& out) {
  char* end = nullptr;
  long v = std::strtol(text.c_str(), &end, 10);
  if (text.empty() || *end != '\0' || v < min || v > max) return false;
  out = v;
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace kessler::server;
  ManagerOptions options;
  std::string listen = "127.0.0.1:50051";
  std::string port_file;
  long max_message_mb = 64;
  for (int i = 1; i < argc; ++i) {
    std::string arg = argv[i];
    if (arg == "--help" || arg == "-h") {
      std::cout << kUsage << "\n" << kRunLimitsUsage;
      return 0;
    }
    if (i + 1 >= argc) return usage_error("unknown option or missing value: " + arg);
    std::string value = argv[++i];
    long n = 0;
    if (arg == "--listen") {
      listen = value;
    } else if (arg == "--db") {
      options.db_path = value;
    } else if (arg == "--runs-at-once") {
      if (!parse_int(value, 1, 1024, n)) return usage_error("--runs-at-once needs an integer 1..1024");
      options.runs_at_once = static_cast<int>(n);
    } else if (arg == "--threads") {
      if (!parse_int(value, 0, 1024, n)) return usage_error("--threads needs an integer 0..1024");
      options.threads_per_run = static_cast<int>(n);
    } else if (arg == "--queue-limit") {
      if (!parse_int(value, 1, 1000000, n)) return usage_error("--queue-limit needs an integer 1..1000000");
      options.queue_limit = static_cast<std::size_t>(n);
    } else if (arg == "--max-ensemble-members") {
      if (!parse_int(value, 1, 1000000, n))
        return usage_error("--max-ensemble-members needs an integer 1..1000000");
      options.max_ensemble_members = static_cast<std::uint64_t>(n);
    } else if (arg == "--max-message-mb") {
      if (!parse_int(value, 1, 2000, n)) return usage_error("--max-message-mb needs an integer 1..2000");
      max_message_mb = n;
    } else if (arg == "--datasets") {
      options.datasets_dir = value;
    } else if (arg == "--traffic-plans") {
      options.traffic_dir = value;
    } else if (arg == "--checkpoint-write-ms") {
      if (!parse_int(value, 0, 86400000, n))
        return usage_error("--checkpoint-write-ms needs an integer 0..86400000");
      options.min_checkpoint_interval = std::chrono::milliseconds(n);
    } else if (arg == "--port-file") {
      port_file = value;
    } else if (std::string error; parse_run_limit_flag(arg, value, options.limits, error)) {
      if (!error.empty()) return usage_error(error);
    } else {
      return usage_error("unknown option " + arg);
    }
  }

  // SIGTERM and SIGINT are taken by sigwait below, not by whichever thread the kernel picks.
  sigset_t signals;
  sigemptyset(&signals);
  sigaddset(&signals, SIGTERM);
  sigaddset(&signals, SIGINT);
  pthread_sigmask(SIG_BLOCK, &signals, nullptr);

  tune_allocator_for_runs();
  try {
    RunManager manager(options);  // the database's folder and files are created private (0700, 0600)
    ApiServer api(manager, listen, static_cast<std::size_t>(max_message_mb) << 20);
    std::string host = listen.substr(0, listen.rfind(':'));
    std::cout << "kesslerd: serving on " << host << ":" << api.port() << ", database " << options.db_path
              << std::endl;
    if (!port_file.empty()) {
      std::string tmp = port_file + ".tmp";
      std::ofstream(tmp) << api.port() << "\n";
      std::filesystem::rename(tmp, port_file);
    }
    int received = 0;
    sigwait(&signals, &received);
    std::cout << "kesslerd: " << (received == SIGTERM ? "SIGTERM" : "SIGINT")
              << ": checkpointing running runs and stopping" << std::endl;
    manager.shutdown();
    api.shutdown(2.0);
    api.wait();
    std::cout << "kesslerd: stopped" << std::endl;
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "kesslerd: " << e.what() << "\n";
    return 1;
  }
}
