// End to end through the real daemon and CLI binaries on loopback: submit, watch, list, query in
// every format; results equal an in-process run of the same scenario; restarts, SIGKILL mid-run and
// SIGTERM keep every run and event exactly once; reconnecting watchers get exactly the rest; bad
// submissions are refused with the right status and the daemon keeps serving.
#include <grpcpp/generic/generic_stub.h>
#include <grpcpp/grpcpp.h>
#include <gtest/gtest.h>
#include <sqlite3.h>

#include <chrono>
#include <filesystem>
#include <future>
#include <map>
#include <random>
#include <set>
#include <thread>

#include "core/scenario/run_builder.hpp"
#include "kessler/v1/service.grpc.pb.h"
#include "tests/service/service_harness.hpp"

namespace kessler {
namespace {

using test::cli;
using test::Daemon;


std::unique_ptr<v1::KesslerService::Stub> connect(const Daemon& d) {
  grpc::ChannelArguments args;
  args.SetMaxReceiveMessageSize(256 << 20);
  return v1::KesslerService::NewStub(
      grpc::CreateCustomChannel(d.address(), grpc::InsecureChannelCredentials(), args));
}

// An event in comparable form: everything deterministic about it, as text.
std::string describe(const v1::RunEvent& e) {
  std::ostringstream s;
  s.precision(17);
  s << e.seq() << " ";
  if (e.has_encounter()) {
    const auto& c = e.encounter();
    s << "enc " << c.id1() << " " << c.id2() << " " << c.tca_s() << " " << c.miss_distance_m() << " "
      << c.kappa() << " " << c.relative_speed_m_s() << " " << c.kind() << " " << c.r1_m().x() << " "
      << c.v2_m_s().z();
  } else if (e.has_burn_up()) {
    s << "burn " << e.burn_up().id() << " " << e.burn_up().time_s() << " " << e.burn_up().altitude_m();
  } else if (e.has_progress()) {
    s << "prog " << e.progress().step() << " " << e.progress().sim_time_s() << " "
      << e.progress().objects_alive();
  }
  return s.str();
}

// The same scenario run in this process, its events described as above.
struct LocalRun {
  std::vector<std::string> events;
  RunSummary summary;
};

class CollectingSink final : public EventSink {
 public:
  std::vector<v1::RunEvent> events;
  void on_encounter(std::uint64_t seq, const Encounter& e) override {
    v1::RunEvent ev;
    ev.set_seq(seq);
    auto* c = ev.mutable_encounter();
    c->set_id1(e.id1);
    c->set_id2(e.id2);
    c->set_tca_s(e.tca_s);
    c->set_miss_distance_m(e.miss_distance_m);
    c->set_kappa(e.kappa);
    c->set_relative_speed_m_s(e.relative_speed_m_s);
    c->set_kind(static_cast<v1::EncounterKind>(e.kind));
    c->mutable_r1_m()->set_x(e.r1_m.x());
    c->mutable_v2_m_s()->set_z(e.v2_m_s.z());
    events.push_back(ev);
  }
  void on_burn_up(std::uint64_t seq, const BurnUp& b) override {
    v1::RunEvent ev;
    ev.set_seq(seq);
    ev.mutable_burn_up()->set_id(b.id);
    ev.mutable_burn_up()->set_time_s(b.time_s);
    ev.mutable_burn_up()->set_altitude_m(b.altitude_m);
    events.push_back(ev);
  }
  void on_progress(std::uint64_t seq, const Progress& p) override {
    v1::RunEvent ev;
    ev.set_seq(seq);
    ev.mutable_progress()->set_step(p.step);
    ev.mutable_progress()->set_sim_time_s(p.sim_time_s);
    ev.mutable_progress()->set_objects_alive(p.objects_alive);
    events.push_back(ev);
  }
  void on_checkpoint(std::uint64_t, std::int64_t, const std::string&) override {}
  void on_finished(const RunSummary&) override {}
  void on_failed(const std::string&) override {}
};

LocalRun run_in_process(const std::string& path) {
  v1::Scenario scenario;
  auto error = parse_scenario(test::read_text(path), scenario);
  if (error) throw std::runtime_error(error->message());
  FieldError build_error;
  BuildOptions options;
  options.threads = 1;  // the daemon runs with its default threads: results must not depend on it
  auto simulation = build_simulation(scenario, options, &build_error);
  if (!simulation) throw std::runtime_error(build_error.message());
  CollectingSink sink;
  RunControl control;
  LocalRun local;
  local.summary = simulation->run(sink, control);
  for (const auto& e : sink.events) local.events.push_back(describe(e));
  return local;
}

v1::Run get_run(v1::KesslerService::Stub& stub, std::int64_t id, grpc::Status* status = nullptr) {
  grpc::ClientContext context;
  v1::GetRunRequest request;
  request.set_run_id(id);
  v1::Run run;
  auto s = stub.GetRun(&context, request, &run);
  if (status) *status = s;
  return run;
}

v1::Run wait_until_ended(v1::KesslerService::Stub& stub, std::int64_t id, int timeout_s = 120) {
  auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(timeout_s);
  for (;;) {
    v1::Run run = get_run(stub, id);
    if (run.state() >= v1::RUN_STATE_SUCCEEDED || std::chrono::steady_clock::now() > deadline) return run;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
}

grpc::Status submit(v1::KesslerService::Stub& stub, const v1::SubmitRunRequest& request, v1::Run& run) {
  grpc::ClientContext context;
  return stub.SubmitRun(&context, request, &run);
}

std::int64_t submit_file(v1::KesslerService::Stub& stub, const std::string& path) {
  v1::SubmitRunRequest request;
  request.set_scenario_text(test::read_text(path));
  v1::Run run;
  auto status = submit(stub, request, run);
  if (!status.ok()) throw std::runtime_error("submit: " + status.error_message());
  return run.id();
}

// Watches from after_seq; stops after max_events numbered events (0: to the end).
std::vector<v1::RunEvent> watch(v1::KesslerService::Stub& stub, std::int64_t id, std::uint64_t after_seq,
                                std::size_t max_events = 0, bool* ended = nullptr) {
  grpc::ClientContext context;
  v1::WatchRunRequest request;
  request.set_run_id(id);
  request.set_after_seq(after_seq);
  auto reader = stub.WatchRun(&context, request);
  std::vector<v1::RunEvent> events;
  v1::RunEvent event;
  bool saw_end = false;
  while (reader->Read(&event)) {
    if (event.has_state()) {
      saw_end = event.state().state() >= v1::RUN_STATE_SUCCEEDED;
      continue;
    }
    // The stream ends with the final state, after every event: an event after a final state is a bug.
    EXPECT_FALSE(saw_end) << "event " << event.seq() << " after the final state";
    events.push_back(event);
    if (max_events && events.size() >= max_events) {
      context.TryCancel();
      break;
    }
  }
  reader->Finish();
  if (ended) *ended = saw_end;
  return events;
}

std::vector<std::string> described(const std::vector<v1::RunEvent>& events) {
  std::vector<std::string> out;
  for (const auto& e : events) out.push_back(describe(e));
  return out;
}

std::vector<v1::Encounter> all_conjunctions(v1::KesslerService::Stub& stub, std::int64_t id) {
  std::vector<v1::Encounter> out;
  v1::ListConjunctionsRequest request;
  request.set_run_id(id);
  request.set_include_evasions(true);
  request.set_page_size(500);
  for (;;) {
    grpc::ClientContext context;
    v1::ListConjunctionsResponse response;
    auto status = stub.ListConjunctions(&context, request, &response);
    if (!status.ok()) throw std::runtime_error(status.error_message());
    out.insert(out.end(), response.conjunctions().begin(), response.conjunctions().end());
    if (response.next_page_token().empty()) return out;
    request.set_page_token(response.next_page_token());
  }
}

std::size_t count_lines(const std::string& text) {
  return static_cast<std::size_t>(std::count(text.begin(), text.end(), '\n'));
}

TEST(ServiceEndToEnd, SubmitWatchListQueryAndRestartMatchAnInProcessRun) {
  TempDir dir;
  LocalRun local = run_in_process(test::kTinyScenario);
  ASSERT_GT(local.summary.conjunctions, 0u) << "the test scenario should produce conjunctions";

  auto daemon = std::make_unique<Daemon>(dir.path() + "/k.db");
  daemon->start();
  const std::string server = " --server " + daemon->address();

  // submit --watch --output json: the last line is the summary object.
  auto submitted = cli(dir, "submit " + test::kTinyScenario + " --watch --output json" + server);
  ASSERT_EQ(submitted.exit_code, 0) << submitted.err;
  std::string summary = submitted.last_line();
  EXPECT_NE(summary.find("\"run_id\":1"), std::string::npos) << summary;
  EXPECT_NE(summary.find("\"state\":\"succeeded\""), std::string::npos) << summary;
  EXPECT_NE(summary.find("\"events_digest\":\"" + local.summary.events_digest + "\""), std::string::npos)
      << summary;
  EXPECT_NE(summary.find("\"state_digest\":\"" + local.summary.state_digest + "\""), std::string::npos)
      << summary;
  EXPECT_NE(summary.find("\"objects_final\":" + std::to_string(local.summary.objects_final)),
            std::string::npos);

  auto stub = connect(*daemon);
  // Every event, in order, equal to the in-process run.
  bool ended = false;
  EXPECT_EQ(described(watch(*stub, 1, 0, 0, &ended)), local.events);
  EXPECT_TRUE(ended);
  auto conjunctions = all_conjunctions(*stub, 1);
  std::vector<std::string> expected_encounters;
  for (const auto& e : local.events)
    if (e.find(" enc ") != std::string::npos) expected_encounters.push_back(e);
  std::vector<std::string> got_encounters;
  for (const auto& c : conjunctions) {
    v1::RunEvent e;
    e.set_seq(c.seq());
    *e.mutable_encounter() = c;
    got_encounters.push_back(describe(e));
  }
  EXPECT_EQ(got_encounters, expected_encounters);

  // runs, show, conjunctions in table, CSV and JSON.
  auto runs = cli(dir, "runs" + server);
  EXPECT_EQ(runs.exit_code, 0);
  EXPECT_NE(runs.out.find("succeeded"), std::string::npos) << runs.out;
  auto runs_json = cli(dir, "runs --output json" + server);
  EXPECT_NE(runs_json.out.find("\"run_id\": 1"), std::string::npos) << runs_json.out;
  auto show = cli(dir, "show 1 --output json" + server);
  EXPECT_EQ(show.exit_code, 0) << show.err;
  EXPECT_EQ(show.last_line(), summary);
  auto show_table = cli(dir, "show 1" + server);
  EXPECT_NE(show_table.out.find("conjunctions by kappa"), std::string::npos);
  EXPECT_NE(show_table.out.find("integrator"), std::string::npos);

  std::size_t n_conj = 0;
  for (const auto& c : conjunctions) n_conj += c.kind() != v1::ENCOUNTER_KIND_EVASION;
  auto csv = cli(dir, "conjunctions 1 --output csv" + server);
  EXPECT_EQ(csv.exit_code, 0) << csv.err;
  EXPECT_EQ(csv.out.rfind("seq,kind,id1,id2,tca_s", 0), 0u) << csv.out.substr(0, 200);
  EXPECT_EQ(count_lines(csv.out), n_conj + 1);
  auto json = cli(dir, "conjunctions 1 --output json" + server);
  EXPECT_EQ(static_cast<std::size_t>(std::count(json.out.begin(), json.out.end(), '{')), n_conj);
  auto table = cli(dir, "conjunctions 1 --limit 3" + server);
  EXPECT_EQ(count_lines(table.out), 5u) << table.out;  // header, 3 rows, count
  auto pairs = cli(dir, "conjunctions 1 --closest-per-pair --output csv" + server);
  std::set<std::pair<std::uint64_t, std::uint64_t>> distinct;
  for (const auto& c : conjunctions)
    if (c.kind() != v1::ENCOUNTER_KIND_EVASION) distinct.insert({c.id1(), c.id2()});
  EXPECT_EQ(count_lines(pairs.out), distinct.size() + 1);

  // Collision probability: sorted largest first, filtered, written as CDMs that `assess` reads back.
  auto by_pc = cli(dir, "conjunctions 1 --sort pc --output csv" + server);
  EXPECT_EQ(by_pc.exit_code, 0) << by_pc.err;
  EXPECT_EQ(count_lines(by_pc.out), n_conj + 1);
  EXPECT_NE(by_pc.out.find(",pc,pc_method,covariance_source,pc_max,pc_max_sigma_m\n"), std::string::npos);
  auto none = cli(dir, "conjunctions 1 --pc-min 1 --output csv" + server);
  EXPECT_EQ(count_lines(none.out), 1u) << none.out;
  EXPECT_EQ(cli(dir, "conjunctions 1 --sort probability" + server).exit_code, 2);
  const std::string cdm_dir = dir.path() + "/cdms";
  auto cdms = cli(dir, "conjunctions 1 --sort pc --limit 2 --output cdm --dir " + cdm_dir + server);
  EXPECT_EQ(cdms.exit_code, 0) << cdms.err;
  std::size_t written = 0;
  for (const auto& file : std::filesystem::directory_iterator(cdm_dir)) {
    ++written;
    auto assessed = cli(dir, "assess " + file.path().string() + " --output json");
    EXPECT_EQ(assessed.exit_code, 0) << assessed.err << assessed.out;
    EXPECT_EQ(assessed.out.rfind("{\"pc\": ", 0), 0u) << assessed.out;
    EXPECT_NE(assessed.out.find("\"cdm_pc\": "), std::string::npos) << assessed.out;
  }
  EXPECT_EQ(written, 2u);

  // Restart: the run and its conjunctions are still there.
  EXPECT_EQ(daemon->terminate(), 0) << daemon->log();
  daemon = std::make_unique<Daemon>(dir.path() + "/k.db");
  daemon->start();
  stub = connect(*daemon);
  EXPECT_EQ(get_run(*stub, 1).state(), v1::RUN_STATE_SUCCEEDED);
  EXPECT_EQ(all_conjunctions(*stub, 1).size(), conjunctions.size());
  EXPECT_EQ(cli(dir, "show 1 --output json --server " + daemon->address()).last_line(), summary);

  // Delete: gone.
  EXPECT_EQ(cli(dir, "delete 1 --server " + daemon->address()).exit_code, 0);
  grpc::Status status;
  get_run(*stub, 1, &status);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::NOT_FOUND);
  EXPECT_EQ(cli(dir, "show 1 --server " + daemon->address()).exit_code, 1);
}

// The step of the run's stored checkpoint (0: none), read beside the daemon (WAL lets a reader in).
std::int64_t stored_checkpoint_step(const std::string& db_path, std::int64_t run_id) {
  sqlite3* db = nullptr;
  std::int64_t step = 0;
  if (sqlite3_open_v2(db_path.c_str(), &db, SQLITE_OPEN_READONLY, nullptr) == SQLITE_OK) {
    sqlite3_busy_timeout(db, 1000);
    sqlite3_stmt* stmt = nullptr;
    if (sqlite3_prepare_v2(db, "SELECT step FROM checkpoints WHERE run_id = ?", -1, &stmt, nullptr) ==
        SQLITE_OK) {
      sqlite3_bind_int64(stmt, 1, run_id);
      if (sqlite3_step(stmt) == SQLITE_ROW) step = sqlite3_column_int64(stmt, 0);
    }
    sqlite3_finalize(stmt);
  }
  sqlite3_close(db);
  return step;
}

// A catalog run through the daemon, global options before the command: the ingest report first in
// submit --watch's JSON and in show, the objects' names in the conjunction listings and the watch stream.
TEST(ServiceEndToEnd, IngestReportAndObjectNamesReachTheCli) {
  TempDir dir;
  auto daemon = std::make_unique<Daemon>(dir.path() + "/k.db");
  daemon->start();
  const std::string server = " --server " + daemon->address();
  const std::string scenario = test::source_path("tests/scenario/data/catalog-small.yaml");
  auto submitted = cli(dir, server + " --output json submit " + scenario + " --watch");
  ASSERT_EQ(submitted.exit_code, 0) << submitted.err;
  const std::string first = submitted.out.substr(0, submitted.out.find('\n'));
  EXPECT_EQ(first.rfind("{\"type\":\"ingest\",\"records\":204,", 0), 0u) << first;
  EXPECT_NE(first.find("\"excluded name\":2"), std::string::npos) << first;
  EXPECT_NE(submitted.last_line().find("\"state\":\"succeeded\""), std::string::npos) << submitted.out;

  auto show = cli(dir, "show 1" + server);
  EXPECT_NE(show.out.find("ingest: 204 records read"), std::string::npos) << show.out;
  auto table = cli(dir, server + " conjunctions 1");
  EXPECT_NE(table.out.find("TIROS 1"), std::string::npos) << table.out;
  EXPECT_NE(table.out.find("KESSLER TWIN"), std::string::npos) << table.out;
  auto csv = cli(dir, "conjunctions 1 --output csv" + server);
  EXPECT_NE(csv.out.find(",TIROS 1,KESSLER TWIN,"), std::string::npos) << csv.out;
  auto json = cli(dir, "conjunctions 1 --output json" + server);
  EXPECT_NE(json.out.find("\"name1\": \"TIROS 1\", \"name2\": \"KESSLER TWIN\""), std::string::npos)
      << json.out;
  EXPECT_NE(json.out.find("\"r1_m\": ["), std::string::npos) << json.out;
  auto watched = cli(dir, "watch 1 --events all --output json" + server);
  EXPECT_EQ(watched.out.rfind("{\"type\":\"ingest\"", 0), 0u) << watched.out.substr(0, 200);
  EXPECT_NE(watched.out.find("\"name1\":\"TIROS 1\",\"name2\":\"KESSLER TWIN\""), std::string::npos);

  auto bad = cli(dir, "runs --bogus" + server);
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("--bogus"), std::string::npos) << bad.err;
}

TEST(ServiceEndToEnd, SigkillMidRunThenRestartCompletesWithTheSameEvents) {
  TempDir dir;
  // The tiny run five times as long (about a second on one thread), so that it is still running when
  // a third is done and a checkpoint is stored, however the machine's load delays this test.
  std::string scenario = test::read_text(test::kTinyScenario);
  const std::string duration = "duration_days: 0.04";
  ASSERT_NE(scenario.find(duration), std::string::npos);
  scenario.replace(scenario.find(duration), duration.size(), "duration_days: 0.2");
  const std::string path = dir.path() + "/longer.yaml";
  test::write_text(path, scenario);
  LocalRun local = run_in_process(path);
  const std::string db = dir.path() + "/k.db";
  auto daemon = std::make_unique<Daemon>(db, std::vector<std::string>{"--threads", "1"});
  daemon->start();
  auto stub = connect(*daemon);
  std::int64_t id = submit_file(*stub, path);
  // Wait until the run is a third done with a checkpoint stored, then kill the daemon outright.
  auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  v1::Run run;
  std::int64_t checkpoint_step = 0;
  do {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
    run = get_run(*stub, id);
    if (checkpoint_step == 0) checkpoint_step = stored_checkpoint_step(db, id);
  } while ((run.progress().step() < run.progress().total_steps() / 3 || checkpoint_step == 0) &&
           run.state() <= v1::RUN_STATE_RUNNING && std::chrono::steady_clock::now() < deadline);
  ASSERT_EQ(run.state(), v1::RUN_STATE_RUNNING) << "the run ended before it could be interrupted";
  daemon->kill9();
  EXPECT_GT(stored_checkpoint_step(db, id), 0) << "the restart must resume from a checkpoint";

  daemon = std::make_unique<Daemon>(db);
  daemon->start();
  stub = connect(*daemon);
  run = wait_until_ended(*stub, id);
  ASSERT_EQ(run.state(), v1::RUN_STATE_SUCCEEDED) << run.error();
  EXPECT_EQ(run.summary().events_digest(), local.summary.events_digest);
  EXPECT_EQ(run.summary().state_digest(), local.summary.state_digest);
  EXPECT_EQ(described(watch(*stub, id, 0)), local.events);  // none lost, none twice
}

// Twenty SIGKILLs at random moments (seeded) across three queued runs, each followed by a restart: every
// run ends with exactly the events and digests of an uninterrupted run, none lost, none twice.
TEST(ServiceEndToEnd, TwentySigkillsAtRandomMomentsAcrossRunsLoseAndDoubleNothing) {
  TempDir dir;
  std::string scenario = test::read_text(test::kTinyScenario);
  const std::string duration = "duration_days: 0.04";
  scenario.replace(scenario.find(duration), duration.size(), "duration_days: 0.5");
  const std::string path = dir.path() + "/longer.yaml";
  test::write_text(path, scenario);
  LocalRun local = run_in_process(path);
  const std::string db = dir.path() + "/k.db";
  const std::vector<std::string> flags{"--threads", "1", "--checkpoint-write-ms", "0"};
  auto daemon = std::make_unique<Daemon>(db, flags);
  daemon->start();
  auto stub = connect(*daemon);
  std::vector<std::int64_t> ids;
  for (int r = 0; r < 3; ++r) ids.push_back(submit_file(*stub, path));
  std::mt19937 rng(44);
  std::uniform_int_distribution<int> delay_ms(20, 400);
  int kills_while_running = 0;
  for (int kill = 0; kill < 20; ++kill) {
    std::this_thread::sleep_for(std::chrono::milliseconds(delay_ms(rng)));
    for (std::int64_t id : ids) kills_while_running += get_run(*stub, id).state() == v1::RUN_STATE_RUNNING;
    daemon->kill9();
    daemon = std::make_unique<Daemon>(db, flags);
    daemon->start();
    stub = connect(*daemon);
  }
  for (std::int64_t id : ids) {
    SCOPED_TRACE("run " + std::to_string(id));
    const v1::Run run = wait_until_ended(*stub, id, 300);
    ASSERT_EQ(run.state(), v1::RUN_STATE_SUCCEEDED) << run.error();
    EXPECT_EQ(run.summary().events_digest(), local.summary.events_digest);
    EXPECT_EQ(run.summary().state_digest(), local.summary.state_digest);
    EXPECT_EQ(described(watch(*stub, id, 0)), local.events);  // none lost, none twice
  }
  EXPECT_GE(kills_while_running, 10) << "too few kills landed while a run was running";
}

TEST(ServiceEndToEnd, SigtermCheckpointsTheRunningRunWhichResumesAtTheNextStart) {
  TempDir dir;
  LocalRun local = run_in_process(test::kTinyScenario);
  auto daemon = std::make_unique<Daemon>(dir.path() + "/k.db");
  daemon->start();
  auto stub = connect(*daemon);
  std::int64_t id = submit_file(*stub, test::kTinyScenario);
  std::int64_t queued = submit_file(*stub, test::kTinyScenario);
  v1::Run run;
  do {
    run = get_run(*stub, id);
  } while (run.progress().step() == 0 && run.state() <= v1::RUN_STATE_RUNNING);
  EXPECT_EQ(daemon->terminate(), 0) << daemon->log();
  daemon = std::make_unique<Daemon>(dir.path() + "/k.db");
  daemon->start();
  stub = connect(*daemon);
  for (std::int64_t r : {id, queued}) {
    run = wait_until_ended(*stub, r);
    ASSERT_EQ(run.state(), v1::RUN_STATE_SUCCEEDED) << run.error();
    EXPECT_EQ(run.summary().events_digest(), local.summary.events_digest);
    EXPECT_EQ(described(watch(*stub, r, 0)), local.events);
  }
}

// kessler cancel, then kessler resume: the run continues from its checkpoint and ends with exactly the
// events and digests of an uninterrupted run; resume is refused for a run that has not failed or been
// cancelled, and for an unknown one.
TEST(ServiceEndToEnd, ACancelledRunResumesFromItsCheckpointAndEndsAsAnUninterruptedRun) {
  TempDir dir;
  std::string scenario = test::read_text(test::kTinyScenario);
  const std::string duration = "duration_days: 0.04";
  scenario.replace(scenario.find(duration), duration.size(), "duration_days: 0.2");
  const std::string path = dir.path() + "/longer.yaml";
  test::write_text(path, scenario);
  LocalRun local = run_in_process(path);
  const std::string db = dir.path() + "/k.db";
  Daemon daemon(db, {"--threads", "1", "--checkpoint-write-ms", "0"});
  daemon.start();
  auto stub = connect(daemon);
  const std::string server = " --server " + daemon.address();
  std::int64_t id = submit_file(*stub, path);
  const std::string run = std::to_string(id);
  v1::Run state;
  do {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
    state = get_run(*stub, id);
  } while (
      (state.progress().step() < state.progress().total_steps() / 3 || stored_checkpoint_step(db, id) == 0) &&
      state.state() <= v1::RUN_STATE_RUNNING);
  ASSERT_EQ(state.state(), v1::RUN_STATE_RUNNING) << "the run ended before it could be cancelled";
  auto refused = cli(dir, "resume " + run + server);
  EXPECT_EQ(refused.exit_code, 1);
  EXPECT_NE(refused.err.find("FAILED_PRECONDITION"), std::string::npos) << refused.err;
  ASSERT_EQ(cli(dir, "cancel " + run + server).exit_code, 0);
  ASSERT_EQ(wait_until_ended(*stub, id).state(), v1::RUN_STATE_CANCELLED);

  auto resumed = cli(dir, "resume " + run + " --output json" + server);
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  // Queued, or already running again by the time the CLI prints.
  EXPECT_NE(resumed.out.find("\"state\": \""), std::string::npos) << resumed.out;
  EXPECT_EQ(resumed.out.find("cancelled"), std::string::npos) << resumed.out;
  state = wait_until_ended(*stub, id);
  ASSERT_EQ(state.state(), v1::RUN_STATE_SUCCEEDED) << state.error();
  EXPECT_EQ(state.summary().events_digest(), local.summary.events_digest);
  EXPECT_EQ(state.summary().state_digest(), local.summary.state_digest);
  EXPECT_EQ(described(watch(*stub, id, 0)), local.events);  // none lost, none twice
  auto again = cli(dir, "resume " + run + server);
  EXPECT_EQ(again.exit_code, 1);
  EXPECT_NE(again.err.find("only a failed or cancelled run resumes"), std::string::npos) << again.err;
  auto unknown = cli(dir, "resume 999" + server);
  EXPECT_EQ(unknown.exit_code, 1);
  EXPECT_NE(unknown.err.find("NOT_FOUND"), std::string::npos) << unknown.err;
}

TEST(ServiceEndToEnd, AWatcherThatReconnectsWithItsLastSequenceGetsExactlyTheRest) {
  TempDir dir;
  auto daemon = std::make_unique<Daemon>(dir.path() + "/k.db");
  daemon->start();
  auto stub = connect(*daemon);
  std::int64_t id = submit_file(*stub, test::kTinyScenario);
  // Several watchers at once; each disconnects now and then and comes back with its last number.
  std::vector<std::vector<v1::RunEvent>> seen(4);
  std::vector<std::thread> watchers;
  for (std::size_t w = 0; w < seen.size(); ++w) {
    watchers.emplace_back([&, w] {
      std::uint64_t cursor = 0;
      bool ended = false;
      for (int round = 0; round < 1000 && !ended; ++round) {
        auto part = watch(*stub, id, cursor, 7 + 5 * w, &ended);
        if (!part.empty()) cursor = part.back().seq();
        seen[w].insert(seen[w].end(), part.begin(), part.end());
      }
    });
  }
  for (auto& t : watchers) t.join();
  ASSERT_EQ(wait_until_ended(*stub, id).state(), v1::RUN_STATE_SUCCEEDED);
  auto all = described(watch(*stub, id, 0));
  ASSERT_FALSE(all.empty());
  for (const auto& s : seen) EXPECT_EQ(described(s), all);
  // And from the middle of a finished run: exactly the tail.
  std::size_t half = all.size() / 2;
  std::uint64_t half_seq = std::stoull(all[half - 1]);
  auto tail = described(watch(*stub, id, half_seq));
  EXPECT_EQ(tail, std::vector<std::string>(all.begin() + static_cast<long>(half), all.end()));
  // The CLI's watch of a finished run replays it and ends with the summary.
  auto replay = cli(dir, "watch " + std::to_string(id) + " --output json --server " + daemon->address());
  EXPECT_EQ(replay.exit_code, 0);
  EXPECT_NE(replay.last_line().find("\"state\":\"succeeded\""), std::string::npos);
}

TEST(ServiceEndToEnd, BadSubmissionsAreRefusedNamingTheProblemAndTheDaemonKeepsServing) {
  TempDir dir;
  auto daemon =
      std::make_unique<Daemon>(dir.path() + "/k.db", std::vector<std::string>{"--max-message-mb", "40"});
  daemon->start();
  auto stub = connect(*daemon);
  const std::string base = test::read_text(test::kTinyScenario);
  struct Case {
    std::string text;
    std::string path;  // expected in the message
  };
  // Each field wrong in turn (appended keys override; the parser takes the last).
  std::vector<Case> cases = {
      {"name: x\ndt_s: -10\npopulation: {synthetic: {objects: 10}}\n", "dt_s"},
      {"name: x\ndt_s: 0\npopulation: {synthetic: {objects: 10}}\n", "dt_s"},
      {"name: x\nduration_days: -1\npopulation: {synthetic: {objects: 10}}\n", "duration_days"},
      {"name: x\nstart_epoch: \"yesterday\"\npopulation: {synthetic: {objects: 10}}\n", "start_epoch"},
      {"name: x\nend_epoch: \"2021-01-01T00:00:00Z\"\npopulation: {synthetic: {objects: 10}}\n", "end_epoch"},
      {"name: x\npopulation: {synthetic: {objects: 10}}\nconjunctions: {kappa_max: 50}\n", "kappa_max"},
      {"name: x\npopulation: {synthetic: {objects: 10}}\nconjunctions: {kappa_max: -1}\n", "kappa_max"},
      {"name: x\npopulation: {synthetic: {objects: 10}}\nburn_up_altitude_km: -5\n", "burn_up_altitude_km"},
      {"name: x\npopulation: {synthetic: {objects: 0}}\n", "population"},
      {"name: x\npopulation: {synthetic: {objects: 10, min_altitude_km: 900, max_altitude_km: 400}}\n",
       "altitude"},
      {"name: x\npopulation: {dataset: no-such-dataset}\n", "population.dataset"},
      {"name: x\npopulation: {synthetic: {objects: 10}}\nprogress_every_steps: -3\n", "progress_every_steps"},
      {"name: x\npopulation: {synthetic: {objects: 10}}\ncheckpoints: {every_steps: -1}\n", "checkpoints"},
      {"name: x\npopulation: {synthetic: {objects: 10}}\nno_such_field: 1\n", "no_such_field"},
      {"name: x\npopulation: {synthetic: {objects: 10}}\nforce_model: {drag: maybe}\n", "force_model.drag"},
      {"name: [unclosed\n", ""},
      {"name: x\n", "population"},
  };
  for (const auto& c : cases) {
    v1::SubmitRunRequest request;
    request.set_scenario_text(c.text);
    v1::Run run;
    auto status = submit(*stub, request, run);
    EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT)
        << c.text << " -> " << status.error_message();
    EXPECT_NE(status.error_message().find(c.path), std::string::npos)
        << c.text << " -> " << status.error_message();
  }
  // A broken inline catalog: element sets with a bad checksum, strict rules refuse it naming the line.
  v1::SubmitRunRequest broken;
  broken.mutable_scenario()->set_name("broken-catalog");
  auto* catalog = broken.mutable_scenario()->mutable_population()->mutable_catalog();
  catalog->set_format(v1::CATALOG_FORMAT_TLE);
  catalog->set_text(
      "SAT A\n"
      "1 25544U 98067A   22021.50000000  .00001234  00000-0  12345-4 0  9991\n"
      "2 25544  51.6400 100.0000 0005000  90.0000 270.0000 15.50000000123456\n");
  broken.mutable_scenario()->mutable_population()->mutable_rules()->set_strict(true);
  v1::Run run;
  auto status = submit(*stub, broken, run);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT) << status.error_message();
  EXPECT_NE(status.error_message().find("population.catalog"), std::string::npos) << status.error_message();
  // Text that is no catalog at all.
  catalog->set_format(v1::CATALOG_FORMAT_UNSPECIFIED);
  catalog->set_text("GARBAGE\nnot a catalog at all\n");
  status = submit(*stub, broken, run);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT) << status.error_message();
  EXPECT_NE(status.error_message().find("population"), std::string::npos) << status.error_message();
  // A 30 MB catalog passes the size limit (and is judged on its content: junk here).
  std::string big(30u << 20, 'x');
  for (std::size_t i = 80; i < big.size(); i += 81) big[i] = '\n';
  catalog->set_text(big);
  status = submit(*stub, broken, run);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT) << status.error_message();
  // One above the daemon's limit is RESOURCE_EXHAUSTED.
  big.resize(45u << 20, 'x');
  catalog->set_text(big);
  status = submit(*stub, broken, run);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED) << status.error_message();

  // Through the CLI: exit 2 and the field on stderr.
  test::write_text(dir.path() + "/bad.yaml", cases[0].text);
  auto bad = cli(dir, "submit " + dir.path() + "/bad.yaml --server " + daemon->address());
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("INVALID_ARGUMENT"), std::string::npos) << bad.err;
  EXPECT_NE(bad.err.find("dt_s"), std::string::npos) << bad.err;
  EXPECT_EQ(cli(dir, "submit").exit_code, 2);
  EXPECT_EQ(cli(dir, "submit --bogus x.yaml").exit_code, 2);
  EXPECT_EQ(cli(dir, "conjunctions notanumber").exit_code, 2);

  // Still serving: a good run goes through.
  std::int64_t id = submit_file(*stub, test::kTinyScenario);
  EXPECT_EQ(wait_until_ended(*stub, id).state(), v1::RUN_STATE_SUCCEEDED);
  EXPECT_TRUE(daemon->alive());
}

TEST(ServiceEndToEnd, StatusCodesForQueueLimitsCancelDeleteAndUnknownRuns) {
  TempDir dir;
  auto daemon =
      std::make_unique<Daemon>(dir.path() + "/k.db", std::vector<std::string>{"--queue-limit", "1"});
  daemon->start();
  auto stub = connect(*daemon);
  // Runs long enough (days) to be cancelled while still running, however fast the machine.
  std::string long_text = test::read_text(test::kTinyScenario);
  long_text.replace(long_text.find("duration_days: 0.04"), 19, "duration_days: 5");
  test::write_text(dir.path() + "/long.yaml", long_text);
  std::int64_t running = submit_file(*stub, dir.path() + "/long.yaml");
  while (get_run(*stub, running).state() == v1::RUN_STATE_QUEUED)
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  std::int64_t queued = submit_file(*stub, dir.path() + "/long.yaml");
  v1::SubmitRunRequest request;
  request.set_scenario_text(test::read_text(test::kTinyScenario));
  v1::Run run;
  EXPECT_EQ(submit(*stub, request, run).error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
  const std::string server = " --server " + daemon->address();
  auto full = cli(dir, "submit " + test::kTinyScenario + server);
  EXPECT_EQ(full.exit_code, 1);
  EXPECT_NE(full.err.find("RESOURCE_EXHAUSTED"), std::string::npos);

  // Deleting a live run is refused; cancelling works for queued and running runs.
  auto del = cli(dir, "delete " + std::to_string(queued) + server);
  EXPECT_EQ(del.exit_code, 1);
  EXPECT_NE(del.err.find("FAILED_PRECONDITION"), std::string::npos) << del.err;
  EXPECT_EQ(cli(dir, "cancel " + std::to_string(queued) + server).exit_code, 0);
  EXPECT_EQ(get_run(*stub, queued).state(), v1::RUN_STATE_CANCELLED);
  EXPECT_EQ(cli(dir, "cancel " + std::to_string(running) + server).exit_code, 0);
  EXPECT_EQ(wait_until_ended(*stub, running).state(), v1::RUN_STATE_CANCELLED);
  auto again = cli(dir, "cancel " + std::to_string(running) + server);
  EXPECT_EQ(again.exit_code, 1);
  EXPECT_NE(again.err.find("FAILED_PRECONDITION"), std::string::npos);
  EXPECT_EQ(cli(dir, "delete " + std::to_string(running) + server).exit_code, 0);

  grpc::Status status;
  get_run(*stub, 999, &status);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::NOT_FOUND);
  auto missing = cli(dir, "watch 999" + server);
  EXPECT_EQ(missing.exit_code, 1);
  EXPECT_NE(missing.err.find("NOT_FOUND"), std::string::npos);
  auto listed = cli(dir, "runs --state cancelled --output csv" + server);
  EXPECT_EQ(count_lines(listed.out), 2u) << listed.out;  // header + the queued run cancelled
  // No daemon at all: exit 1 with a clear message.
  auto unreachable = cli(dir, "runs", "KESSLER_SERVER=127.0.0.1:1");
  EXPECT_EQ(unreachable.exit_code, 1);
  EXPECT_NE(unreachable.err.find("UNAVAILABLE"), std::string::npos) << unreachable.err;
}

// The standard health service answers SERVING (what grpc_health_probe asks), through a generic call
// since the health proto's stubs are not part of the build.
TEST(ServiceEndToEnd, HealthServiceAnswersServing) {
  TempDir dir;
  Daemon daemon(dir.path() + "/k.db");
  daemon.start();
  grpc::GenericStub generic(grpc::CreateChannel(daemon.address(), grpc::InsecureChannelCredentials()));
  grpc::ClientContext context;
  grpc::Slice empty(std::string{});
  grpc::ByteBuffer request(&empty, 1);  // HealthCheckRequest{service: ""}: the whole server
  grpc::ByteBuffer response;
  std::promise<grpc::Status> done;
  generic.UnaryCall(&context, "/grpc.health.v1.Health/Check", grpc::StubOptions(), &request, &response,
                    [&](grpc::Status status) { done.set_value(status); });
  grpc::Status status = done.get_future().get();
  ASSERT_TRUE(status.ok()) << status.error_message();
  std::vector<grpc::Slice> slices;
  ASSERT_TRUE(response.Dump(&slices).ok());
  std::string bytes;
  for (const auto& slice : slices) bytes.append(reinterpret_cast<const char*>(slice.begin()), slice.size());
  EXPECT_EQ(bytes, std::string("\x08\x01", 2));  // HealthCheckResponse{status: SERVING}
}

}  // namespace
}  // namespace kessler
