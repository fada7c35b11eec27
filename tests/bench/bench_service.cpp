// kessler-bench service: the same scenario through the daemon (gRPC API, store, event hub, watchers)
// and in-process, and the store's event throughput on its own. Built when the daemon is
// (KESSLER_WITH_SERVER, set by kessler_server when the run builder is there to link).
//
// Both sides run the same v1::Scenario with the same threads per run, on a thread of their own, and
// take the same checkpoints (the in-process consumer keeps the latest in memory). The daemon side is
// a RunManager with its gRPC server in this process on loopback; its wall time runs from SubmitRun to
// the moment the last watcher has received the final state after every event. The watchers (clients
// in this process) share the machine's cores with the daemon and the simulation.
#if defined(KESSLER_WITH_SERVER)
#include <dirent.h>
#include <grpcpp/grpcpp.h>
#include <pthread.h>
#include <time.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <sstream>
#include <thread>

#include "core/scenario/run_builder.hpp"
#include "kessler/v1/service.grpc.pb.h"
#include "server/api_server.hpp"
#include "server/auth.hpp"
#include "server/run_manager.hpp"
#include "server/store.hpp"
#include "tests/bench/bench.hpp"

namespace kessler::bench {
namespace {

// The in-process consumer: counts events and keeps the latest checkpoint in memory, as a program
// that embeds the core would.
class CountingSink final : public EventSink {
 public:
  std::uint64_t events = 0;
  std::string last_checkpoint;
  void on_encounter(std::uint64_t, const Encounter&) override { ++events; }
  void on_burn_up(std::uint64_t, const BurnUp&) override { ++events; }
  void on_progress(std::uint64_t, const Progress&) override { ++events; }
  void on_checkpoint(std::uint64_t, std::int64_t, const std::string& bytes) override {
    last_checkpoint = bytes;
  }
  void on_finished(const RunSummary&) override {}
  void on_failed(const std::string&) override {}
};

std::string temp_dir() {
  std::string pattern = "/tmp/kessler-bench-XXXXXX";
  if (!mkdtemp(pattern.data())) throw std::runtime_error("mkdtemp");
  return pattern;
}

std::string read_file(const std::string& path) {
  std::ifstream in(path);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

double thread_cpu_s() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

// CPU seconds so far of each live thread of this process, summed by thread name (the daemon names
// its own: kessler-run, kessler-relay, kessler-store), from /proc/self/task/*/schedstat (ns).
std::map<std::string, double> cpu_by_thread_name() {
  std::map<std::string, double> out;
  DIR* dir = opendir("/proc/self/task");
  if (!dir) return out;
  while (dirent* entry = readdir(dir)) {
    if (entry->d_name[0] == '.') continue;
    const std::string base = std::string("/proc/self/task/") + entry->d_name;
    std::string name;
    std::getline(std::ifstream(base + "/comm"), name);
    double ns = 0;
    if (std::ifstream(base + "/schedstat") >> ns) out[name] += ns * 1e-9;
  }
  closedir(dir);
  return out;
}

// One run's figures, in-process or through the daemon.
struct Measured {
  double wall_s = 0;       // in-process: build + run; daemon: SubmitRun to the last watcher's final state
  double run_cpu_s = 0;    // CPU of the simulation's thread (build + run)
  double other_cpu_s = 0;  // CPU of every other thread of this process meanwhile
  double relay_cpu_s = 0, store_cpu_s = 0;  // daemon: of those, its relay and store writer threads
  // Daemon: where the wall time outside the run went: SubmitRun to the run's start (as the store has
  // it), the run's start to its end in the store less the simulation's own run time (build, relay
  // drain, store flush), and from there to the last watcher's final state.
  double to_start_s = 0, around_run_s = 0, to_watchers_s = 0;
  PhaseTimers timers;  // the run's own (the simulation thread's wall per phase)
  std::uint64_t events = 0;
  std::string digest;
  int watchers_complete = 0;  // daemon: watchers that saw every event and then the final state
};

PhaseTimers from_proto(const v1::PhaseTimers& t) {
  PhaseTimers out;
  out.integrator_s = t.integrator_s();
  out.burn_up_s = t.burn_up_s();
  out.grid_s = t.grid_s();
  out.detection_s = t.detection_s();
  out.output_s = t.output_s();
  out.checkpoint_s = t.checkpoint_s();
  out.total_s = t.total_s();
  return out;
}

// Build + run in this process, on a thread of its own like the daemon's run.
Measured in_process(const v1::Scenario& scenario, int threads, bool checkpoints = true) {
  Measured m;
  std::string failure;
  const double cpu0 = process_cpu_s();
  const double t0 = now_s();
  std::thread runner([&] {
    pthread_setname_np(pthread_self(), "bench-local");
    BuildOptions options;
    options.threads = threads;
    options.checkpoints = checkpoints;
    FieldError error;
    auto simulation = build_simulation(scenario, options, &error);
    if (!simulation) {
      failure = error.message();
      return;
    }
    CountingSink sink;
    RunControl control;
    RunSummary summary = simulation->run(sink, control);
    m.timers = summary.timers;
    m.digest = summary.events_digest;
    m.events = summary.events;
    m.run_cpu_s = thread_cpu_s();
  });
  runner.join();
  m.wall_s = now_s() - t0;
  m.other_cpu_s = process_cpu_s() - cpu0 - m.run_cpu_s;
  if (!failure.empty()) throw std::runtime_error(failure);
  return m;
}

// The same scenario through a RunManager and its gRPC server in this process, over loopback, with
// `watchers` clients streaming WatchRun from the submission on.
// secure: over TLS (the test CA's localhost certificate, tests/data/tls) with a submit token on every
// call, as a daemon facing a network serves; else plaintext without tokens.
Measured through_daemon(const v1::Scenario& scenario, int threads, int watchers, int gather_ms,
                        int checkpoint_write_ms, bool secure = false) {
  std::string dir = temp_dir();
  server::ManagerOptions options;
  options.db_path = dir + "/bench.db";
  options.threads_per_run = threads;
  if (gather_ms >= 0) options.relay_gather = std::chrono::milliseconds(gather_ms);
  if (checkpoint_write_ms >= 0)
    options.min_checkpoint_interval = std::chrono::milliseconds(checkpoint_write_ms);
  Measured result;
  {
    server::RunManager manager(options);
    server::ApiOptions api_options;
    std::string token;
    std::shared_ptr<grpc::ChannelCredentials> credentials = grpc::InsecureChannelCredentials();
    if (secure) {
      const std::string tls = std::string(KESSLER_BENCH_TEST_DATA_DIR) + "/tls/";
      api_options.tls = server::load_tls({tls + "server.pem", tls + "server.key", ""});
      token = server::create_token(dir + "/tokens", "bench", server::Role::kSubmit);
      api_options.auth = std::make_shared<const server::Authenticator>(dir + "/tokens");
      grpc::SslCredentialsOptions ssl;
      ssl.pem_root_certs = read_file(tls + "ca.pem");
      credentials = grpc::SslCredentials(ssl);
    }
    server::ApiServer api(manager, "127.0.0.1:0", api_options);
    auto channel =
        grpc::CreateChannel((secure ? "localhost:" : "127.0.0.1:") + std::to_string(api.port()), credentials);
    auto stub = v1::KesslerService::NewStub(channel);
    auto authorize = [&](grpc::ClientContext& context) {
      if (!token.empty()) context.AddMetadata("authorization", "Bearer " + token);
    };
    v1::SubmitRunRequest request;
    *request.mutable_scenario() = scenario;
    request.set_threads(threads);
    v1::Run run;
    const auto threads0 = cpu_by_thread_name();
    const double cpu0 = process_cpu_s();
    const double t0_unix =
        std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
    const double t0 = now_s();
    grpc::ClientContext submit_context;
    authorize(submit_context);
    auto status = stub->SubmitRun(&submit_context, request, &run);
    if (!status.ok()) throw std::runtime_error("submit: " + status.error_message());
    std::vector<std::thread> clients;
    std::vector<std::uint64_t> counts(static_cast<std::size_t>(watchers), 0);
    std::vector<char> ended(static_cast<std::size_t>(watchers), 0);
    std::atomic<double> last_end{t0};
    for (int w = 0; w < watchers; ++w) {
      clients.emplace_back([&, w] {
        grpc::ClientContext context;
        authorize(context);
        v1::WatchRunRequest watch;
        watch.set_run_id(run.id());
        auto reader = stub->WatchRun(&context, watch);
        v1::RunEvent event;
        while (reader->Read(&event)) {
          if (!event.has_state()) {
            ++counts[static_cast<std::size_t>(w)];
          } else if (event.state().state() == v1::RUN_STATE_SUCCEEDED) {
            ended[static_cast<std::size_t>(w)] = 1;
            const double t = now_s();
            double prev = last_end.load();
            while (t > prev && !last_end.compare_exchange_weak(prev, t)) {
            }
          }
        }
        reader->Finish();
      });
    }
    if (watchers == 0) {
      // No watcher: the run's end as GetRun sees it, polled every 10 ms.
      for (;;) {
        grpc::ClientContext context;
        authorize(context);
        v1::GetRunRequest get;
        get.set_run_id(run.id());
        v1::Run now;
        if (stub->GetRun(&context, get, &now).ok() && server::is_terminal(now.state())) break;
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
      }
      last_end = now_s();
    }
    for (auto& t : clients) t.join();
    result.wall_s = last_end.load() - t0;
    const double process_cpu = process_cpu_s() - cpu0;
    auto threads1 = cpu_by_thread_name();
    auto delta = [&](const std::string& name) {
      auto before = threads0.find(name);
      return threads1[name] - (before == threads0.end() ? 0.0 : before->second);
    };
    result.run_cpu_s = delta("kessler-run");
    result.relay_cpu_s = manager.relay_cpu_s();  // its thread has ended with the run
    result.store_cpu_s = delta("kessler-store");
    result.other_cpu_s = process_cpu - result.run_cpu_s;
    grpc::ClientContext get_context;
    authorize(get_context);
    v1::GetRunRequest get;
    get.set_run_id(run.id());
    stub->GetRun(&get_context, get, &run);
    if (run.state() != v1::RUN_STATE_SUCCEEDED) throw std::runtime_error("the daemon's run did not succeed");
    result.events = run.summary().events();
    result.digest = run.summary().events_digest();
    result.timers = from_proto(run.summary().timers());
    result.to_start_s = run.started_unix_s() - t0_unix;
    result.around_run_s = run.finished_unix_s() - run.started_unix_s() - result.timers.total_s;
    result.to_watchers_s = t0_unix + result.wall_s - run.finished_unix_s();
    for (int w = 0; w < watchers; ++w)
      if (ended[static_cast<std::size_t>(w)] && counts[static_cast<std::size_t>(w)] == run.last_seq())
        ++result.watchers_complete;
    manager.shutdown();
    api.shutdown(1.0);
  }
  std::filesystem::remove_all(dir);
  return result;
}

// Events per second through the store's writer: `n` encounter events, timed to the last commit, and
// per CPU second of the writer thread.
double store_throughput(std::uint64_t n, double& per_cpu_s) {
  std::string dir = temp_dir();
  double rate = 0;
  {
    server::Store store(dir + "/store.db");
    std::int64_t id = store.create_run(v1::Scenario(), 0, 0);
    // The events are built first, so the figure is the writer's alone (the daemon builds them on its relay
    // thread).
    std::vector<std::shared_ptr<const v1::RunEvent>> events;
    events.reserve(n);
    for (std::uint64_t s = 1; s <= n; ++s) {
      auto e = std::make_shared<v1::RunEvent>();
      e->set_run_id(id);
      e->set_seq(s);
      auto* c = e->mutable_encounter();
      c->set_id1(s % 16000);
      c->set_id2(16000 + s % 997);
      c->set_tca_s(s * 0.5);
      c->set_miss_distance_m(100.0 + s % 1000);
      c->set_kappa((s % 1000) / 100.0);
      c->mutable_r1_m()->set_x(7e6);
      c->mutable_v1_m_s()->set_y(7.5e3);
      c->mutable_r2_m()->set_x(7e6 + 1);
      c->mutable_v2_m_s()->set_z(7.5e3);
      events.push_back(std::move(e));
    }
    double t0 = now_s();
    for (auto& e : events) store.append_event(std::move(e));
    store.flush();
    rate = static_cast<double>(n) / (now_s() - t0);
    per_cpu_s = static_cast<double>(n) / store.writer_cpu_s();
  }
  std::filesystem::remove_all(dir);
  return rate;
}

int bench_service(int argc, char** argv) {
  // kesslerd's allocator settings, for both sides alike (the process hosts both).
  server::tune_allocator_for_runs();
  Args args(argc, argv);
  args.allow_only({"--scenario", "--objects", "--screening-km", "--checkpoint-every-steps", "--watchers",
                   "--repeats", "--threads", "--store-events", "--relay-gather-ms", "--checkpoint-write-ms",
                   "--tls"});
  std::string path =
      args.get("--scenario", std::string(KESSLER_DATASETS_DIR) + "/../scenarios/synthetic-small.yaml");
  const auto objects = args.get_int("--objects", 8000);                        // 0: as the scenario file says
  const double screening_km = args.get_double("--screening-km", 0);            // 0: as the scenario file says
  const auto checkpoint_every = args.get_int("--checkpoint-every-steps", -1);  // -1: as the file says
  const int watchers = static_cast<int>(args.get_int("--watchers", 10));
  const int repeats = static_cast<int>(args.get_int("--repeats", 8));
  const int threads = static_cast<int>(args.get_int("--threads", 1));  // per-core cost, as every bench
  const auto store_events = static_cast<std::uint64_t>(args.get_int("--store-events", 500000));
  // The daemon's knobs, -1: its defaults.
  const int gather_ms = static_cast<int>(args.get_int("--relay-gather-ms", -1));
  const int checkpoint_write_ms = static_cast<int>(args.get_int("--checkpoint-write-ms", -1));
  // 1: each repeat also runs the daemon over TLS with a token, against the plaintext one.
  const bool tls = args.get_int("--tls", 0) != 0;
  if (watchers < 0 || repeats < 1 || threads < 1 || objects < 0 || screening_km < 0 ||
      checkpoint_every < -1) {
    std::cerr << "kessler-bench service: --watchers >= 0, --repeats >= 1, --threads >= 1, --objects >= 0, "
                 "--screening-km >= 0, --checkpoint-every-steps >= 0\n";
    return 2;
  }
  v1::Scenario scenario;
  if (auto error = parse_scenario(read_file(path), scenario)) {
    std::cerr << "kessler-bench service: " << path << ": " << error->message() << "\n";
    return 2;
  }
  if (objects > 0) {
    auto* population = scenario.mutable_population();
    if (population->has_synthetic())
      population->mutable_synthetic()->set_objects(static_cast<std::uint64_t>(objects));
    else
      population->set_max_objects(static_cast<std::uint64_t>(objects));
  }
  if (screening_km > 0) scenario.mutable_conjunctions()->set_screening_distance_km(screening_km);
  if (checkpoint_every >= 0) scenario.mutable_checkpoints()->set_every_steps(checkpoint_every);
  if (auto error = validate_scenario(scenario)) {
    std::cerr << "kessler-bench service: " << error->message() << "\n";
    return 2;
  }
  const SimulationConfig config = to_simulation_config(scenario, threads);

  std::map<std::string, std::vector<double>> f;  // figure -> one value per repeat
  Measured local, daemon;
  bool digests_equal = true;
  int watchers_complete_min = watchers;
  for (int r = 0; r < repeats; ++r) {
    // Alternate which goes first, so warm caches and load drifts fall on both sides alike.
    if (r % 2 == 0) local = in_process(scenario, threads);
    Measured secure;
    if (tls && r % 2 == 1)
      secure = through_daemon(scenario, threads, watchers, gather_ms, checkpoint_write_ms, true);
    daemon = through_daemon(scenario, threads, watchers, gather_ms, checkpoint_write_ms);
    if (tls && r % 2 == 0)
      secure = through_daemon(scenario, threads, watchers, gather_ms, checkpoint_write_ms, true);
    if (r % 2 == 1) local = in_process(scenario, threads);
    if (tls) {
      f["tls_wall"].push_back(secure.wall_s);
      f["tls_ratio"].push_back(secure.wall_s / daemon.wall_s);
      f["tls_other_cpu"].push_back(secure.other_cpu_s);
      // The daemon's CPU (run and every other thread): what TLS and tokens cost, unskewed by other load.
      f["tls_cpu_ratio"].push_back((secure.run_cpu_s + secure.other_cpu_s) /
                                   (daemon.run_cpu_s + daemon.other_cpu_s));
      digests_equal = digests_equal && secure.digest == local.digest;
      watchers_complete_min = std::min(watchers_complete_min, secure.watchers_complete);
      std::cout << "repeat " << r + 1 << ": TLS and tokens " << secure.wall_s << " s (all other threads "
                << secure.other_cpu_s << " s cpu), plaintext " << daemon.wall_s << " s, ratio "
                << secure.wall_s / daemon.wall_s << std::endl;
    }
    // As `kessler run --local` runs it: no checkpoints (the daemon takes them for crash recovery).
    const Measured bare = in_process(scenario, threads, false);
    f["local_wall"].push_back(local.wall_s);
    f["daemon_wall"].push_back(daemon.wall_s);
    f["bare_wall"].push_back(bare.wall_s);
    f["ratio"].push_back(daemon.wall_s / local.wall_s);
    f["local_run"].push_back(local.timers.total_s);
    f["daemon_run"].push_back(daemon.timers.total_s);
    f["local_output"].push_back(local.timers.output_s);
    f["daemon_output"].push_back(daemon.timers.output_s);
    f["local_checkpoint"].push_back(local.timers.checkpoint_s);
    f["daemon_checkpoint"].push_back(daemon.timers.checkpoint_s);
    f["local_run_cpu"].push_back(local.run_cpu_s);
    f["daemon_run_cpu"].push_back(daemon.run_cpu_s);
    f["daemon_other_cpu"].push_back(daemon.other_cpu_s);
    f["relay_cpu"].push_back(daemon.relay_cpu_s);
    f["store_cpu"].push_back(daemon.store_cpu_s);
    f["to_start"].push_back(daemon.to_start_s);
    f["around_run"].push_back(daemon.around_run_s);
    f["to_watchers"].push_back(daemon.to_watchers_s);
    digests_equal = digests_equal && daemon.digest == local.digest && bare.digest == local.digest;
    watchers_complete_min = std::min(watchers_complete_min, daemon.watchers_complete);
    std::cout << "repeat " << r + 1 << ": in-process " << local.wall_s << " s (run " << local.timers.total_s
              << " s), daemon " << daemon.wall_s << " s (run " << daemon.timers.total_s << " s; cpu: run "
              << daemon.run_cpu_s << " s, relay " << daemon.relay_cpu_s << " s, store " << daemon.store_cpu_s
              << " s, all other threads " << daemon.other_cpu_s << " s), ratio "
              << daemon.wall_s / local.wall_s << "; in-process without checkpoints " << bare.wall_s << " s; "
              << daemon.watchers_complete << "/" << watchers << " watchers saw every event; " << daemon.events
              << " events" << std::endl;
  }
  std::vector<double> store_rates, store_cpu_rates;
  for (int r = 0; r < std::min(repeats, 3); ++r) {
    double per_cpu = 0;
    store_rates.push_back(store_throughput(store_events, per_cpu));
    store_cpu_rates.push_back(per_cpu);
  }
  auto med = [&](const char* key) { return median(f[key]); };
  const auto& ratios = f["ratio"];
  JsonLine line;
  line.add("bench", std::string("service"))
      .add("scenario", path)
      .add("scenario_name", scenario.name())
      .add("objects", static_cast<std::int64_t>(objects))
      .add("steps", static_cast<std::int64_t>(daemon.timers.total_s > 0 ? total_steps_of(config) : 0))
      .add("screening_km", scenario.conjunctions().screening_distance_km())
      .add("checkpoint_every_steps", static_cast<std::int64_t>(config.checkpoint_every_steps))
      .add("threads_per_run", static_cast<std::int64_t>(threads))
      .add("relay_gather_ms", static_cast<std::int64_t>(
                                  gather_ms >= 0 ? gather_ms : server::ManagerOptions().relay_gather.count()))
      .add("checkpoint_write_ms",
           static_cast<std::int64_t>(checkpoint_write_ms >= 0
                                         ? checkpoint_write_ms
                                         : server::ManagerOptions().min_checkpoint_interval.count()))
      .add("watchers", static_cast<std::int64_t>(watchers))
      .add("watchers_complete", static_cast<std::int64_t>(watchers_complete_min))
      .add("events", static_cast<std::int64_t>(daemon.events))
      .add("events_per_s", static_cast<double>(daemon.events) / med("local_wall"))
      .add("in_process_wall_s", med("local_wall"))
      .add("daemon_wall_s", med("daemon_wall"))
      .add("overhead_ratio", med("daemon_wall") / med("local_wall"))
      .add("overhead_ratio_paired", median(ratios))
      .add("overhead_ratio_min", *std::min_element(ratios.begin(), ratios.end()))
      .add("overhead_ratio_max", *std::max_element(ratios.begin(), ratios.end()))
      .add("in_process_no_checkpoints_wall_s", med("bare_wall"))
      .add("overhead_ratio_vs_no_checkpoints", med("daemon_wall") / med("bare_wall"))
      .add("in_process_run_s", med("local_run"))
      .add("daemon_run_s", med("daemon_run"))
      .add("in_process_output_s", med("local_output"))
      .add("daemon_output_s", med("daemon_output"))
      .add("daemon_submit_to_start_s", med("to_start"))
      .add("daemon_build_drain_flush_s", med("around_run"))
      .add("daemon_end_to_last_watcher_s", med("to_watchers"))
      .add("in_process_checkpoint_s", med("local_checkpoint"))
      .add("daemon_checkpoint_s", med("daemon_checkpoint"))
      .add("in_process_run_cpu_s", med("local_run_cpu"))
      .add("daemon_run_cpu_s", med("daemon_run_cpu"))
      .add("daemon_other_cpu_s", med("daemon_other_cpu"))
      .add("relay_cpu_s", med("relay_cpu"))
      .add("store_writer_cpu_s", med("store_cpu"))
      .add("events_per_s_stored", median(store_rates))
      .add("events_per_writer_cpu_s", median(store_cpu_rates))
      .add("digests_equal", static_cast<std::int64_t>(digests_equal))
      .add("repeats", static_cast<std::int64_t>(repeats));
  if (tls) {
    const auto& tls_ratios = f["tls_ratio"];
    line.add("tls_daemon_wall_s", med("tls_wall"))
        .add("tls_over_plaintext_ratio", median(tls_ratios))
        .add("tls_over_plaintext_ratio_min", *std::min_element(tls_ratios.begin(), tls_ratios.end()))
        .add("tls_over_plaintext_ratio_max", *std::max_element(tls_ratios.begin(), tls_ratios.end()))
        .add("tls_daemon_other_cpu_s", med("tls_other_cpu"))
        .add("tls_over_plaintext_cpu_ratio", med("tls_cpu_ratio"))
        .add("tls_over_plaintext_cpu_ratio_min",
             *std::min_element(f["tls_cpu_ratio"].begin(), f["tls_cpu_ratio"].end()))
        .add("tls_over_plaintext_cpu_ratio_max",
             *std::max_element(f["tls_cpu_ratio"].begin(), f["tls_cpu_ratio"].end()));
  }
  line.print();
  return 0;
}

}  // namespace

KESSLER_BENCH("service", "one scenario through kesslerd's API (with watchers) vs in-process; store events/s",
              bench_service);

}  // namespace kessler::bench

#endif  // KESSLER_WITH_SERVER
