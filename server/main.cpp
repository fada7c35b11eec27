// kesslerd: the Kessler daemon. Hosts simulation runs behind a gRPC API and keeps them in SQLite.
#include <signal.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <optional>
#include <string>

#include "server/api_server.hpp"
#include "server/auth.hpp"
#include "server/http/http_server.hpp"
#include "server/run_manager.hpp"
#include "server/transport.hpp"

namespace {

const char* const kUsage = R"(kesslerd - the Kessler simulation daemon

usage: kesslerd [options]
       kesslerd token create --role read|submit|admin --tokens FILE [--name NAME]

Accepts scenario runs over gRPC (kessler.v1.KesslerService, with the standard health service and
server reflection), runs them in order, streams their events and keeps runs, events, conjunctions and
checkpoints in a SQLite database. Runs left running by a crash resume from their last checkpoint at
start; SIGTERM or SIGINT checkpoints running runs and exits cleanly.

options:
  --listen HOST:PORT    address to serve on (default 127.0.0.1:50051; port 0 picks a free one). A
                        non-loopback address needs --tls-cert/--tls-key and --tokens, or --insecure
  --tls-cert FILE       serve TLS with this PEM certificate chain (and --tls-key)
  --tls-key FILE        the certificate's PEM private key
  --tls-client-ca FILE  mutual TLS: clients must present a certificate this PEM CA signed
  --tokens FILE         bearer tokens and their roles (kesslerd token create); every call then needs
                        one. Reread on SIGHUP
  --insecure            allow a non-loopback --listen without TLS or tokens (warns at start and in
                        every answer's "kessler-warning" metadata, which kessler health prints)
  --max-runs-per-token N
                        runs queued and running per read or submit token (default 100; 0: no limit)
  --max-watches-per-token N
                        WatchRun streams open per read or submit token (default 32; 0: no limit)
  --max-watches N       WatchRun streams open in all (default 512; 0: no limit)
  --max-requests-per-s R
                        expensive calls (submissions, conjunctions, stats, fragments, ensembles) per
                        second per read or submit token, in bursts of 2 s (default 20; 0: no limit)
  --db PATH             SQLite database, created when missing, private to the user (default
                        var/kessler.db)
  --runs-at-once N      runs simulated at the same time; the rest queue in order (default 1)
  --threads N           OpenMP threads per run unless a submission asks otherwise (default 0: all cores)
  --queue-limit N       queued runs accepted before SubmitRun answers RESOURCE_EXHAUSTED (default 1000)
  --max-ensemble-members N
                        most members SubmitEnsemble takes; more is INVALID_ARGUMENT (default 1000)
  --max-message-mb N    largest request accepted, e.g. a scenario with an inline catalog, and largest
                        answer sent (default 64)
  --datasets DIR        bundled datasets (default: the build's deploy/datasets)
  --traffic-plans DIR   shipped launch plans, a scenario's traffic.plans (default: the build's
                        deploy/traffic)
  --checkpoint-write-ms N
                        write a run's checkpoints to the database at most every N ms; a newer one
                        replaces one still waiting (default 1000; 0: every checkpoint as it comes)
  --mpi-launcher LINE   compute each run on an MPI job started by LINE, e.g. "mpirun -np 8 --hostfile
                        H" or "srun --ntasks 8": the daemon runs LINE kessler-mpi SCENARIO --event-stream
                        and stores, streams and checkpoints the run as its own (events bit for bit those
                        of a run in the daemon; a failed job fails the run, resumable from its last
                        checkpoint). Off by default
  --mpi-program PATH    the kessler-mpi the launcher starts on every node (default: the one beside
                        kesslerd)
  --mpi-work-dir DIR    where each MPI run's scenario is written for the ranks to read: on a cluster a
                        directory every node sees (default: the system's temporary directory)
  --mpi-retries N       a job that ends without its run's end (a rank or node lost) is started again
                        from the run's last checkpoint up to N times before the run fails (default 0;
                        a failed run resumes later with 'kessler resume')
  --port-file PATH      write the port listened on to PATH once serving (for scripts and tests)
  --http HOST:PORT      also serve the web dashboard (runs, live progress, conjunctions, figures) on
                        HOST:PORT (off by default; port 0 picks a free one); the dashboard has no
                        tokens, so HOST must be loopback unless --insecure
  --http-port-file PATH write the dashboard's port to PATH once serving
  --help                this text

Limits of per-token kind hold read and submit tokens; the admin tokens and the tokenless default (the
operator) are held by the daemon-wide limits only. A limit reached answers RESOURCE_EXHAUSTED naming it.
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

bool parse_rate(const std::string& text, double& out) {
  char* end = nullptr;
  double v = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0' || !std::isfinite(v) || v < 0 || v > 1e6) return false;
  out = v;
  return true;
}

// kesslerd token create --role R --tokens FILE [--name NAME]: prints the new token once.
int token_command(int argc, char** argv) {
  using namespace kessler::server;
  if (argc < 3 || std::string(argv[2]) != "create")
    return usage_error("token: the only subcommand is create (kesslerd token create --role R --tokens FILE)");
  std::string role, path, name;
  for (int i = 3; i < argc; ++i) {
    std::string arg = argv[i];
    if (i + 1 >= argc) return usage_error("token create: missing value of " + arg);
    std::string value = argv[++i];
    if (arg == "--role")
      role = value;
    else if (arg == "--tokens")
      path = value;
    else if (arg == "--name")
      name = value;
    else
      return usage_error("token create: unknown option " + arg);
  }
  auto parsed = parse_role(role);
  if (!parsed) return usage_error("token create: --role must be read, submit or admin");
  if (path.empty()) return usage_error("token create: --tokens FILE is required");
  try {
    if (name.empty()) {
      // The first free "<role>-N".
      std::size_t n = 1;
      if (std::filesystem::exists(path)) n += read_tokens_file(path).size();
      name = role + "-" + std::to_string(n);
    }
    std::string token = create_token(path, name, *parsed);
    std::cerr
        << "kesslerd: added token '" << name << "' (role " << role << ") to " << path
        << "; it is shown once, only its hash is kept. A running kesslerd rereads the file on SIGHUP.\n";
    std::cout << token << std::endl;
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "kesslerd: " << e.what() << "\n";
    return 1;
  }
}

// The MPI options hang together: a program to start and a directory to write in, for a launcher.
std::string check_mpi_options(kessler::server::MpiLaunch& mpi) {
  if (mpi.launcher.empty()) {
    if (!mpi.program.empty() || !mpi.work_dir.empty() || mpi.retries > 0)
      return "--mpi-program, --mpi-work-dir and --mpi-retries need --mpi-launcher";
    return "";
  }
  if (mpi.program.empty()) mpi.program = kessler::server::default_mpi_program();
  if (::access(mpi.program.c_str(), X_OK) != 0)
    return "--mpi-program: " + mpi.program + " is not an executable file (build with -DKESSLER_MPI=ON)";
  std::error_code ec;
  if (!mpi.work_dir.empty() && !std::filesystem::is_directory(mpi.work_dir, ec))
    return "--mpi-work-dir: " + mpi.work_dir + " is not a directory";
  return "";
}

struct Security {
  kessler::server::TlsFiles tls;
  std::string tokens_path;
  bool insecure = false;
};

// Loopback serves as it is; any other address needs TLS and tokens, or --insecure (with its warning).
// The warning to send with every answer, or "" ; nullopt when the daemon must refuse to start.
std::optional<std::string> exposure_warning(const kessler::server::ListenAddress& address,
                                            const Security& s) {
  if (kessler::server::is_loopback_host(address.host)) return std::string();
  const bool tls = !s.tls.cert.empty();
  const bool tokens = !s.tokens_path.empty();
  if (tls && tokens) return std::string();
  if (!s.insecure) return std::nullopt;
  return "insecure: kesslerd serves " + address.host + " without " +
         (tls      ? "tokens"
          : tokens ? "TLS"
                   : "TLS or tokens") +
         " (--insecure)";
}

// One of the flags of TLS, tokens and limits: true when `arg` is one, with `error` set when its value
// is wrong.
bool security_flag(const std::string& arg, const std::string& value, Security& security,
                   kessler::server::LimitOptions& limits, std::string& error) {
  long n = 0;
  auto count = [&](std::uint64_t& out, long max) {
    if (parse_int(value, 0, max, n))
      out = static_cast<std::uint64_t>(n);
    else
      error = arg + " needs an integer 0.." + std::to_string(max);
  };
  if (arg == "--tls-cert") {
    security.tls.cert = value;
  } else if (arg == "--tls-key") {
    security.tls.key = value;
  } else if (arg == "--tls-client-ca") {
    security.tls.client_ca = value;
  } else if (arg == "--tokens") {
    security.tokens_path = value;
  } else if (arg == "--max-runs-per-token") {
    count(limits.runs_per_token, 1000000);
  } else if (arg == "--max-watches-per-token") {
    count(limits.watches_per_token, 100000);
  } else if (arg == "--max-watches") {
    count(limits.watches, 100000);
  } else if (arg == "--max-requests-per-s") {
    if (!parse_rate(value, limits.requests_per_s_per_token)) error = arg + " needs a number 0..1000000";
  } else {
    return false;
  }
  return true;
}

// The flags of TLS and tokens together, and whether the address may be served with them: a message
// when not, else "" with `warning` set to what every answer carries ("" for none).
std::string check_exposure(const kessler::server::ListenAddress& address, const Security& security,
                           std::string& warning) {
  if (security.tls.cert.empty() != security.tls.key.empty()) return "--tls-cert and --tls-key go together";
  if (!security.tls.client_ca.empty() && security.tls.cert.empty())
    return "--tls-client-ca needs --tls-cert and --tls-key";
  auto exposure = exposure_warning(address, security);
  if (!exposure)
    return "--listen " + address.host + ":" + std::to_string(address.port) +
           " is not loopback: serving it needs --tls-cert, --tls-key and --tokens, or --insecure";
  warning = *exposure;
  return "";
}

// Written whole (a rename) so a reader never sees a partial number.
void write_port_file(const std::string& path, int port) {
  std::string tmp = path + ".tmp";
  std::ofstream(tmp) << port << "\n";
  std::filesystem::rename(tmp, path);
}

struct Ports {
  std::string port_file;       // the gRPC port, once serving
  std::string http_address;    // the dashboard's HOST:PORT; empty: off
  std::string http_port_file;  // the dashboard's port, once serving
};

// Serves until SIGTERM or SIGINT (SIGHUP rereads the tokens); the exit code.
int serve(const kessler::server::ManagerOptions& options, kessler::server::ApiOptions api_options,
          const Security& security, const kessler::server::ListenAddress& address, const Ports& ports,
          sigset_t signals) {
  using namespace kessler::server;
  const std::string listen = address.host + ":" + std::to_string(address.port);
  try {
    if (!security.tls.cert.empty()) api_options.tls = load_tls(security.tls);
    auto auth = std::make_shared<Authenticator>(security.tokens_path);
    api_options.auth = auth;
    RunManager manager(options);  // the database's folder and files are created private (0700, 0600)
    ApiServer api(manager, listen, api_options);
    std::cout << "kesslerd: serving on " << address.host << ":" << api.port()
              << (api_options.tls ? " (TLS" : " (plaintext")
              << (api_options.tls && !security.tls.client_ca.empty() ? ", client certificates" : "")
              << (auth->enabled() ? ", " + std::to_string(auth->size()) + " tokens)" : ", no tokens)")
              << ", database " << options.db_path << std::endl;
    if (!api_options.warning.empty()) std::cerr << "kesslerd: WARNING: " << api_options.warning << std::endl;
    std::unique_ptr<HttpServer> http;
    if (!ports.http_address.empty()) {
      http = std::make_unique<HttpServer>(manager, ports.http_address);
      std::cout << "kesslerd: dashboard on http://"
                << ports.http_address.substr(0, ports.http_address.rfind(':')) << ":" << http->port() << "/"
                << std::endl;
      if (!ports.http_port_file.empty()) write_port_file(ports.http_port_file, http->port());
    }
    if (!ports.port_file.empty()) write_port_file(ports.port_file, api.port());
    int received = 0;
    while (sigwait(&signals, &received) == 0 && received == SIGHUP) {
      try {
        auth->reload();
        std::cout << "kesslerd: SIGHUP: " << auth->size() << " tokens from " << security.tokens_path
                  << std::endl;
      } catch (const std::exception& e) {
        std::cerr << "kesslerd: SIGHUP: kept the tokens loaded before: " << e.what() << std::endl;
      }
    }
    std::cout << "kesslerd: " << (received == SIGTERM ? "SIGTERM" : "SIGINT")
              << ": checkpointing running runs and stopping" << std::endl;
    if (http) http->shutdown();
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

}  // namespace

int main(int argc, char** argv) {
  using namespace kessler::server;
  if (argc >= 2 && std::string(argv[1]) == "token") return token_command(argc, argv);
  ManagerOptions options;
  ApiOptions api_options;
  Security security;
  std::string listen = "127.0.0.1:50051";
  Ports ports;
  long max_message_mb = 64;
  for (int i = 1; i < argc; ++i) {
    std::string arg = argv[i];
    if (arg == "--help" || arg == "-h") {
      std::cout << kUsage << "\n" << kRunLimitsUsage;
      return 0;
    }
    if (arg == "--insecure") {
      security.insecure = true;
      continue;
    }
    if (i + 1 >= argc) return usage_error("unknown option or missing value: " + arg);
    std::string value = argv[++i];
    long n = 0;
    std::string flag_error;
    if (arg == "--listen") {
      listen = value;
    } else if (security_flag(arg, value, security, api_options.limits, flag_error)) {
      if (!flag_error.empty()) return usage_error(flag_error);
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
    } else if (arg == "--mpi-launcher") {
      std::string error;
      auto words = split_launcher(value, error);
      if (!words) return usage_error("--mpi-launcher: " + error);
      options.mpi.launcher = *words;
    } else if (arg == "--mpi-program") {
      options.mpi.program = value;
    } else if (arg == "--mpi-work-dir") {
      options.mpi.work_dir = value;
    } else if (arg == "--mpi-retries") {
      if (!parse_int(value, 0, 100, n)) return usage_error("--mpi-retries needs an integer 0..100");
      options.mpi.retries = static_cast<int>(n);
    } else if (arg == "--port-file") {
      ports.port_file = value;
    } else if (arg == "--http") {
      ports.http_address = value;
    } else if (arg == "--http-port-file") {
      ports.http_port_file = value;
    } else if (std::string error; parse_run_limit_flag(arg, value, options.limits, error)) {
      if (!error.empty()) return usage_error(error);
    } else {
      return usage_error("unknown option " + arg);
    }
  }

  if (auto error = check_mpi_options(options.mpi); !error.empty()) return usage_error(error);
  std::string address_error;
  auto address = parse_listen_address(listen, address_error);
  if (!address) return usage_error(address_error);
  if (auto error = check_exposure(*address, security, api_options.warning); !error.empty())
    return usage_error(error);
  api_options.max_message_bytes = static_cast<std::size_t>(max_message_mb) << 20;
  if (!ports.http_address.empty()) {
    auto http = parse_listen_address(ports.http_address, address_error);
    if (!http) return usage_error("--http: " + address_error);
    if (!is_loopback_host(http->host) && !security.insecure)
      return usage_error("--http " + ports.http_address +
                         " is not loopback: the dashboard has no tokens; serve it on loopback (reach it "
                         "through an SSH tunnel) or pass --insecure");
  }

  // SIGTERM and SIGINT (stop) and SIGHUP (reread the tokens) are taken by sigwait below, not by
  // whichever thread the kernel picks.
  sigset_t signals;
  sigemptyset(&signals);
  sigaddset(&signals, SIGTERM);
  sigaddset(&signals, SIGINT);
  sigaddset(&signals, SIGHUP);
  pthread_sigmask(SIG_BLOCK, &signals, nullptr);

  tune_allocator_for_runs();
  return serve(options, api_options, security, *address, ports, signals);
}
