// The daemon under store faults, in this process with its gRPC API on loopback: a write failure in the
// middle of a run fails that run with the error, reads and health go on (the API NOT_SERVING, the server
// SERVING), submissions are UNAVAILABLE, a queued run waits, and once the store can write again the
// failed run's end is written, the queued run runs and new submissions are taken; earlier runs intact.
// A run that emits more events than its limit fails saying so.
#include <grpcpp/generic/generic_stub.h>
#include <grpcpp/grpcpp.h>
#include <gtest/gtest.h>

#include <chrono>
#include <future>
#include <thread>

#include "core/scenario/run_builder.hpp"
#include "server/api_server.hpp"
#include "server/run_manager.hpp"
#include "tests/service/temp_dir.hpp"

namespace kessler {
namespace {

using server::RunManager;
using server::ServiceError;

// A synthetic run of `days`, with conjunctions and progress every step.
std::string synthetic(double days) {
  return "name: faults\nduration_days: " + std::to_string(days) +
         "\ndt_s: 10\npopulation:\n  synthetic:\n    objects: 400\n    min_altitude_km: 500\n"
         "    max_altitude_km: 600\nconjunctions:\n  screening_distance_km: 40\nprogress_every_steps: 1\n"
         "checkpoints:\n  every_steps: 5\nseed: 3\n";
}

// One thread a run, every checkpoint written, the store probed every 50 ms while it cannot write.
server::ManagerOptions fault_options(const TempDir& dir) {
  server::ManagerOptions options;
  options.db_path = dir.path() + "/k.db";
  options.threads_per_run = 1;
  options.store_probe_interval = std::chrono::milliseconds(50);
  options.min_checkpoint_interval = std::chrono::milliseconds(0);
  return options;
}

v1::Run submit(RunManager& m, const std::string& text) {
  v1::SubmitRunRequest request;
  request.set_scenario_text(text);
  return m.submit(request);
}

v1::Run wait_for(RunManager& m, std::int64_t id, bool (*done)(const v1::Run&), int timeout_s = 120) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(timeout_s);
  v1::Run run = m.get(id);
  while (!done(run) && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    run = m.get(id);
  }
  return run;
}

bool ended(const v1::Run& r) {
  return server::is_terminal(r.state());
}

// The health service's answer for `service` ("" is the whole server): 1 SERVING, 2 NOT_SERVING.
int health(const std::string& address, const std::string& service) {
  grpc::GenericStub generic(grpc::CreateChannel(address, grpc::InsecureChannelCredentials()));
  grpc::ClientContext context;
  std::string request_bytes;
  if (!service.empty()) request_bytes = std::string("\x0a", 1) + static_cast<char>(service.size()) + service;
  grpc::Slice slice(request_bytes);
  grpc::ByteBuffer request(&slice, 1);
  grpc::ByteBuffer response;
  std::promise<grpc::Status> done;
  generic.UnaryCall(&context, "/grpc.health.v1.Health/Check", grpc::StubOptions(), &request, &response,
                    [&](grpc::Status status) { done.set_value(status); });
  if (!done.get_future().get().ok()) return -1;
  std::vector<grpc::Slice> slices;
  if (!response.Dump(&slices).ok()) return -1;
  std::string bytes;
  for (const auto& s : slices) bytes.append(reinterpret_cast<const char*>(s.begin()), s.size());
  return bytes.size() == 2 ? bytes[1] : 0;
}

TEST(StoreFaultsEndToEnd, AWriteFailureFailsTheRunAndTheDaemonServesWaitsAndRecovers) {
  TempDir dir;
  RunManager m(fault_options(dir));
  server::ApiServer api(m, "127.0.0.1:0", 64 << 20);
  const std::string address = "127.0.0.1:" + std::to_string(api.port());

  const v1::Run before = wait_for(m, submit(m, synthetic(0.01)).id(), ended);
  ASSERT_EQ(before.state(), v1::RUN_STATE_SUCCEEDED) << before.error();
  v1::ListConjunctionsRequest list;
  list.set_run_id(before.id());
  const std::uint64_t total_before = m.conjunctions(list).total();
  const std::int64_t victim = submit(m, synthetic(5.0)).id();
  const std::int64_t queued = submit(m, synthetic(0.01)).id();
  const v1::Run running = wait_for(m, victim, [](const v1::Run& r) { return r.progress().step() >= 20; });
  ASSERT_EQ(running.state(), v1::RUN_STATE_RUNNING);

  m.store().fail_writes_for_test("database or disk is full");
  const v1::Run failed = wait_for(m, victim, ended);
  EXPECT_EQ(failed.state(), v1::RUN_STATE_FAILED);
  EXPECT_NE(failed.error().find("database or disk is full"), std::string::npos) << failed.error();
  // Reads and health go on; submissions wait; the queued run waits.
  EXPECT_EQ(m.get(before.id()).summary().events_digest(), before.summary().events_digest());
  EXPECT_EQ(m.conjunctions(list).total(), total_before);
  EXPECT_FALSE(m.store_writable());
  try {
    submit(m, synthetic(0.01));
    ADD_FAILURE() << "a submission was taken while the store cannot write";
  } catch (const ServiceError& e) {
    EXPECT_EQ(e.code, ServiceError::Code::kUnavailable);
    EXPECT_NE(std::string(e.what()).find("disk is full"), std::string::npos) << e.what();
  }
  const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (health(address, "kessler.v1.KesslerService") != 2 && std::chrono::steady_clock::now() < until)
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  EXPECT_EQ(health(address, "kessler.v1.KesslerService"), 2);  // NOT_SERVING: no submissions
  EXPECT_EQ(health(address, ""), 1);                           // SERVING: reads
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  EXPECT_EQ(m.get(queued).state(), v1::RUN_STATE_QUEUED);

  // Space returns: the store says so by itself, the failed run's end is written, the queued run runs.
  m.store().fail_writes_for_test("");
  const v1::Run after_queue = wait_for(m, queued, ended);
  EXPECT_EQ(after_queue.state(), v1::RUN_STATE_SUCCEEDED) << after_queue.error();
  EXPECT_TRUE(m.store_writable());
  const auto stored = m.store().get_run(victim, false);
  ASSERT_TRUE(stored);
  EXPECT_EQ(stored->state(), v1::RUN_STATE_FAILED);
  EXPECT_NE(stored->error().find("disk is full"), std::string::npos);
  const v1::Run fresh = wait_for(m, submit(m, synthetic(0.01)).id(), ended);
  EXPECT_EQ(fresh.state(), v1::RUN_STATE_SUCCEEDED) << fresh.error();
  EXPECT_EQ(fresh.summary().events_digest(), before.summary().events_digest());  // same scenario, same run
  EXPECT_EQ(health(address, "kessler.v1.KesslerService"), 1);
}

TEST(StoreFaultsEndToEnd, ARunThatEmitsMoreEventsThanItsLimitFailsSayingSo) {
  TempDir dir;
  server::ManagerOptions options;
  options.db_path = dir.path() + "/k.db";
  options.threads_per_run = 1;
  options.limits.max_events = 30;
  RunManager m(options);
  const v1::Run run = wait_for(m, submit(m, synthetic(0.1)).id(), ended);
  EXPECT_EQ(run.state(), v1::RUN_STATE_FAILED);
  EXPECT_NE(run.error().find("more than 30 events"), std::string::npos) << run.error();
  EXPECT_NE(run.error().find("--max-run-events"), std::string::npos) << run.error();
  EXPECT_LE(m.store().max_seq(run.id()), 30u);
}

// ResumeRun after a storage fault: the failed run continues from its last checkpoint once the store can
// write again, and ends with the digests and the events of the same scenario run without a fault.
TEST(StoreFaultsEndToEnd, ARunFailedByAFullDiskResumesAndEndsAsAnUninterruptedRun) {
  TempDir dir;
  RunManager m(fault_options(dir));
  const v1::Run reference = wait_for(m, submit(m, synthetic(0.3)).id(), ended);
  ASSERT_EQ(reference.state(), v1::RUN_STATE_SUCCEEDED) << reference.error();
  auto expect_refused = [&](std::int64_t id, ServiceError::Code code, const std::string& says) {
    try {
      m.resume(id);
      ADD_FAILURE() << "run " << id << " was resumed";
    } catch (const ServiceError& e) {
      EXPECT_EQ(e.code, code);
      EXPECT_NE(std::string(e.what()).find(says), std::string::npos) << e.what();
    }
  };
  expect_refused(reference.id(), ServiceError::Code::kFailedPrecondition, "is succeeded");
  expect_refused(999, ServiceError::Code::kNotFound, "not found");

  const std::int64_t victim = submit(m, synthetic(0.3)).id();
  const v1::Run running = wait_for(m, victim, [](const v1::Run& r) { return r.progress().step() >= 100; });
  ASSERT_EQ(running.state(), v1::RUN_STATE_RUNNING);
  expect_refused(victim, ServiceError::Code::kFailedPrecondition, "is running");
  m.store().fail_writes_for_test("database or disk is full");
  ASSERT_EQ(wait_for(m, victim, ended).state(), v1::RUN_STATE_FAILED);
  m.store().fail_writes_for_test("");
  const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (!m.store_writable() && std::chrono::steady_clock::now() < until)
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  ASSERT_TRUE(m.store().latest_checkpoint(victim)) << "the failed run kept no checkpoint";

  const v1::Run queued = m.resume(victim);
  EXPECT_EQ(queued.state(), v1::RUN_STATE_QUEUED);
  EXPECT_TRUE(queued.error().empty()) << queued.error();
  const v1::Run resumed = wait_for(m, victim, ended);
  ASSERT_EQ(resumed.state(), v1::RUN_STATE_SUCCEEDED) << resumed.error();
  EXPECT_EQ(resumed.summary().events_digest(), reference.summary().events_digest());
  EXPECT_EQ(resumed.summary().state_digest(), reference.summary().state_digest());
  EXPECT_EQ(resumed.summary().conjunctions(), reference.summary().conjunctions());
  EXPECT_EQ(m.store().max_seq(victim), m.store().max_seq(reference.id()));  // none lost, none twice
  v1::ListConjunctionsRequest list;
  list.set_include_evasions(true);
  list.set_run_id(reference.id());
  const std::uint64_t expected = m.conjunctions(list).total();
  list.set_run_id(victim);
  EXPECT_EQ(m.conjunctions(list).total(), expected);
}

}  // namespace
}  // namespace kessler
