// The service in this process: a RunManager over a database in a temporary folder and its gRPC API on
// 127.0.0.1 (a free port), with a client stub. The end-to-end suites that need the manager's hooks
// (ManagerOptions) or its direct calls use it instead of a kesslerd child process (service_harness.hpp).
#pragma once

#include <grpcpp/grpcpp.h>

#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/scenario/run_builder.hpp"
#include "core/simulation/breakups.hpp"
#include "core/simulation/simulation.hpp"
#include "kessler/v1/service.grpc.pb.h"
#include "server/api_server.hpp"
#include "server/run_manager.hpp"
#include "tests/service/temp_dir.hpp"

namespace kessler::test {

class InProcessService {
 public:
  // `adjust` sets options beyond the database path (threads, runs at once, hooks) before the manager starts.
  explicit InProcessService(const std::function<void(server::ManagerOptions&)>& adjust = {}) {
    server::ManagerOptions options;
    options.db_path = dir.path() + "/k.db";
    if (adjust) adjust(options);
    manager = std::make_unique<server::RunManager>(options);
    api = std::make_unique<server::ApiServer>(*manager, "127.0.0.1:0", 64 << 20);
    address = "127.0.0.1:" + std::to_string(api->port());
    stub = v1::KesslerService::NewStub(grpc::CreateChannel(address, grpc::InsecureChannelCredentials()));
  }
  ~InProcessService() {
    api.reset();  // the server stops before the manager it serves
    manager.reset();
  }
  InProcessService(const InProcessService&) = delete;
  InProcessService& operator=(const InProcessService&) = delete;

  v1::Run submit(const v1::Scenario& scenario) {
    v1::SubmitRunRequest request;
    *request.mutable_scenario() = scenario;
    grpc::ClientContext context;
    v1::Run run;
    const grpc::Status status = stub->SubmitRun(&context, request, &run);
    if (!status.ok()) throw std::runtime_error("submit: " + status.error_message());
    return run;
  }

  // The run's stream after `after_seq` to its end, state changes left out (the last one in `state`).
  std::vector<v1::RunEvent> watch(std::int64_t run_id, std::uint64_t after_seq = 0, bool no_progress = false,
                                  v1::RunState* state = nullptr) {
    grpc::ClientContext context;
    v1::WatchRunRequest request;
    request.set_run_id(run_id);
    request.set_after_seq(after_seq);
    request.set_no_progress(no_progress);
    auto reader = stub->WatchRun(&context, request);
    std::vector<v1::RunEvent> out;
    for (v1::RunEvent e; reader->Read(&e);) {
      if (!e.has_state())
        out.push_back(e);
      else if (state)
        *state = e.state().state();
    }
    const grpc::Status status = reader->Finish();
    if (!status.ok()) throw std::runtime_error("watch: " + status.error_message());
    return out;
  }

  TempDir dir;
  std::unique_ptr<server::RunManager> manager;
  std::unique_ptr<server::ApiServer> api;
  std::string address;
  std::unique_ptr<v1::KesslerService::Stub> stub;
};

// A scenario's text parsed (throws on an error: the suites' scenarios are fixed).
inline v1::Scenario parsed_scenario(const std::string& text) {
  v1::Scenario scenario;
  if (parse_scenario(text, scenario)) throw std::runtime_error("the suite's scenario does not parse");
  return scenario;
}

// The first object of the scenario's population as built for a run.
inline ObjectId first_object(const v1::Scenario& scenario) {
  FieldError error;
  auto simulation = build_simulation(scenario, BuildOptions{}, &error);
  if (!simulation) throw std::runtime_error(error.message());
  return simulation->population().id[0];
}

// Options that make every run explode `target` (an 800 kg object) at `step`, for the suites that follow a
// breakup's fragments through the service.
inline std::function<void(server::ManagerOptions&)> explode_at(ObjectId target, std::int64_t step) {
  return [target, step](server::ManagerOptions& options) {
    options.adjust_config = [target, step](SimulationConfig& c) {
      c.breakups.enabled = true;
      ScheduledBreakup explosion;
      explosion.step = step;
      explosion.kind = BreakupKind::kExplosion;
      explosion.object_ids = {target};
      explosion.masses_kg = {800.0};
      c.breakups.scheduled = {explosion};
    };
  };
}

}  // namespace kessler::test
