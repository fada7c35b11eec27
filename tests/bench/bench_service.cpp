// kessler-bench service: the same scenario through the daemon (gRPC API, store, event hub, watchers)
// and in-process, and the store's event throughput on its own. Built when the daemon is
// (KESSLER_WITH_SERVER, set by kessler_server when the run builder is there to link).
#if defined(KESSLER_WITH_SERVER)
#include <grpcpp/grpcpp.h>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <sstream>
#include <thread>

#include "core/scenario/run_builder.hpp"
#include "kessler/v1/service.grpc.pb.h"
#include "server/api_server.hpp"
#include "server/run_manager.hpp"
#include "server/store.hpp"
#include "tests/bench/bench.hpp"

namespace kessler::bench {
namespace {

class CountingSink final : public EventSink {
 public:
  std::uint64_t events = 0;
  void on_encounter(std::uint64_t, const Encounter&) override { ++events; }
  void on_burn_up(std::uint64_t, const BurnUp&) override { ++events; }
  void on_progress(std::uint64_t, const Progress&) override { ++events; }
  void on_checkpoint(std::uint64_t, std::int64_t, const std::string&) override {}
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

// Wall seconds of build + run in this process.
double in_process(const v1::Scenario& scenario, int threads, std::string& digest) {
  double t0 = now_s();
  BuildOptions options;
  options.threads = threads;
  FieldError error;
  auto simulation = build_simulation(scenario, options, &error);
  if (!simulation) throw std::runtime_error(error.message());
  CountingSink sink;
  RunControl control;
  digest = simulation->run(sink, control).events_digest;
  return now_s() - t0;
}

struct DaemonResult {
  double wall_s = 0;
  std::uint64_t events = 0;
  int watchers_complete = 0;
  std::string digest;
};

// Wall seconds from SubmitRun to the end of the run as the watchers see it.
DaemonResult through_daemon(const std::string& scenario_text, int threads, int watchers) {
  std::string dir = temp_dir();
  server::ManagerOptions options;
  options.db_path = dir + "/bench.db";
  options.threads_per_run = threads;
  DaemonResult result;
  {
    server::RunManager manager(options);
    server::ApiServer api(manager, "127.0.0.1:0", 64u << 20);
    auto channel =
        grpc::CreateChannel("127.0.0.1:" + std::to_string(api.port()), grpc::InsecureChannelCredentials());
    auto stub = v1::KesslerService::NewStub(channel);
    v1::SubmitRunRequest request;
    request.set_scenario_text(scenario_text);
    v1::Run run;
    double t0 = now_s();
    grpc::ClientContext submit_context;
    auto status = stub->SubmitRun(&submit_context, request, &run);
    if (!status.ok()) throw std::runtime_error("submit: " + status.error_message());
    std::vector<std::thread> threads_;
    std::vector<std::uint64_t> counts(static_cast<std::size_t>(std::max(watchers, 1)), 0);
    std::atomic<int> complete{0};
    std::atomic<double> last_end{0};
    for (int w = 0; w < std::max(watchers, 1); ++w) {
      threads_.emplace_back([&, w] {
        grpc::ClientContext context;
        v1::WatchRunRequest watch;
        watch.set_run_id(run.id());
        auto reader = stub->WatchRun(&context, watch);
        v1::RunEvent event;
        bool ended = false;
        while (reader->Read(&event)) {
          if (event.has_state()) {
            ended = event.state().state() == v1::RUN_STATE_SUCCEEDED;
            if (ended) {
              double t = now_s();
              double prev = last_end.load();
              while (t > prev && !last_end.compare_exchange_weak(prev, t)) {
              }
            }
          } else {
            ++counts[static_cast<std::size_t>(w)];
          }
        }
        reader->Finish();
        if (ended) ++complete;
      });
    }
    for (auto& t : threads_) t.join();
    result.wall_s = last_end.load() - t0;
    grpc::ClientContext get_context;
    v1::GetRunRequest get;
    get.set_run_id(run.id());
    stub->GetRun(&get_context, get, &run);
    result.events = run.summary().events();
    result.digest = run.summary().events_digest();
    result.watchers_complete = 0;
    for (int w = 0; w < std::max(watchers, 1); ++w)
      if (counts[static_cast<std::size_t>(w)] >= run.last_seq() && run.last_seq() > 0)
        ++result.watchers_complete;
    if (watchers == 0) result.watchers_complete = 0;
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
    // The events are built first, so the figure is the writer's alone (the daemon builds them on the
    // simulation's thread).
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
  Args args(argc, argv);
  args.allow_only({"--scenario", "--watchers", "--repeats", "--threads", "--store-events"});
  std::string path =
      args.get("--scenario", std::string(KESSLER_DATASETS_DIR) + "/../scenarios/synthetic-small.yaml");
  int watchers = static_cast<int>(args.get_int("--watchers", 10));
  int repeats = static_cast<int>(args.get_int("--repeats", 3));
  int threads = static_cast<int>(args.get_int("--threads", 1));  // per-core cost, as every bench
  auto store_events = static_cast<std::uint64_t>(args.get_int("--store-events", 500000));
  std::string text = read_file(path);
  v1::Scenario scenario;
  if (auto error = parse_scenario(text, scenario)) {
    std::cerr << "kessler-bench service: " << path << ": " << error->message() << "\n";
    return 2;
  }
  std::vector<double> local_s, daemon_s, store_rates;
  DaemonResult last;
  std::string local_digest;
  for (int r = 0; r < repeats; ++r) {
    // Alternate which goes first, so warm caches and load drifts fall on both sides alike.
    if (r % 2 == 0) local_s.push_back(in_process(scenario, threads, local_digest));
    last = through_daemon(text, threads, watchers);
    daemon_s.push_back(last.wall_s);
    if (r % 2 == 1) local_s.push_back(in_process(scenario, threads, local_digest));
    std::cout << "repeat " << r + 1 << ": in-process " << local_s.back() << " s, daemon " << daemon_s.back()
              << " s with " << watchers << " watchers (" << last.watchers_complete << " saw every event), "
              << last.events << " events" << std::endl;
  }
  std::vector<double> store_cpu_rates;
  for (int r = 0; r < repeats; ++r) {
    double per_cpu = 0;
    store_rates.push_back(store_throughput(store_events, per_cpu));
    store_cpu_rates.push_back(per_cpu);
  }
  double local_wall = median(local_s), daemon_wall = median(daemon_s);
  JsonLine line;
  line.add("bench", std::string("service"))
      .add("scenario", path)
      .add("watchers", static_cast<std::int64_t>(watchers))
      .add("watchers_complete", static_cast<std::int64_t>(last.watchers_complete))
      .add("events", static_cast<std::int64_t>(last.events))
      .add("in_process_wall_s", local_wall)
      .add("daemon_wall_s", daemon_wall)
      .add("overhead_ratio", daemon_wall / local_wall)
      .add("events_per_s_stored", median(store_rates))
      .add("events_per_writer_cpu_s", median(store_cpu_rates))
      .add("digests_equal", static_cast<std::int64_t>(last.digest == local_digest))
      .add("repeats", static_cast<std::int64_t>(repeats));
  line.print();
  return 0;
}

}  // namespace

KESSLER_BENCH("service", "one scenario through kesslerd's API (with watchers) vs in-process; store events/s",
              bench_service);

}  // namespace kessler::bench

#endif  // KESSLER_WITH_SERVER
