// Breakups end to end: a run whose configuration schedules an explosion (set through the run manager's
// adjust_config, the core's own settings) on a daemon in this process, its gRPC API on loopback and the
// real kessler binary: WatchRun streams the breakup in sequence, ListFragments returns its fragments,
// GetRunStats counts objects by type, the CLI prints the breakup and lists the fragments; bad requests
// are refused with their status.
#include <grpcpp/grpcpp.h>
#include <gtest/gtest.h>

#include <sstream>

#include "core/scenario/run_builder.hpp"
#include "kessler/v1/service.grpc.pb.h"
#include "server/api_server.hpp"
#include "server/run_manager.hpp"
#include "tests/service/service_harness.hpp"

namespace kessler {
namespace {

using test::cli;

const char* const kScenario = R"yaml(
name: breakup-e2e
duration_days: 0.005
dt_s: 10
population:
  dataset: leo-19647
  max_objects: 300
conjunctions:
  screening_distance_km: 12
progress_every_steps: 4
checkpoints:
  every_steps: 8
seed: 5
)yaml";

constexpr std::int64_t kExplosionStep = 6;

// The first object of the scenario's population: the one that explodes.
ObjectId first_object(const v1::Scenario& scenario) {
  FieldError error;
  auto simulation = build_simulation(scenario, BuildOptions{}, &error);
  if (!simulation) throw std::runtime_error(error.message());
  return simulation->population().id[0];
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream s(text);
  for (std::string line; std::getline(s, line);)
    if (!line.empty()) out.push_back(line);
  return out;
}

class BreakupEndToEnd : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_FALSE(parse_scenario(kScenario, scenario_).has_value());
    target_ = first_object(scenario_);
    server::ManagerOptions options;
    options.db_path = dir_.path() + "/k.db";
    options.adjust_config = [target = target_](SimulationConfig& c) {
      c.breakups.enabled = true;
      ScheduledBreakup explosion;
      explosion.step = kExplosionStep;
      explosion.kind = BreakupKind::kExplosion;
      explosion.object_ids = {target};
      explosion.masses_kg = {800.0};
      c.breakups.scheduled = {explosion};
    };
    manager_ = std::make_unique<server::RunManager>(options);
    api_ = std::make_unique<server::ApiServer>(*manager_, "127.0.0.1:0", 64 << 20);
    address_ = "127.0.0.1:" + std::to_string(api_->port());
    stub_ = v1::KesslerService::NewStub(grpc::CreateChannel(address_, grpc::InsecureChannelCredentials()));
  }
  void TearDown() override {
    api_.reset();  // the server stops before the manager it serves
    manager_.reset();
  }

  TempDir dir_;
  v1::Scenario scenario_;
  ObjectId target_ = 0;
  std::unique_ptr<server::RunManager> manager_;
  std::unique_ptr<server::ApiServer> api_;
  std::string address_;
  std::unique_ptr<v1::KesslerService::Stub> stub_;
};

TEST_F(BreakupEndToEnd, AScheduledExplosionReachesWatchFragmentsStatsAndTheCli) {
  v1::SubmitRunRequest submit;
  *submit.mutable_scenario() = scenario_;
  v1::Run run;
  {
    grpc::ClientContext context;
    ASSERT_TRUE(stub_->SubmitRun(&context, submit, &run).ok());
  }
  // The whole stream: numbered events without gaps, one breakup among them.
  std::vector<v1::RunEvent> events;
  v1::RunState final_state = v1::RUN_STATE_UNSPECIFIED;
  {
    grpc::ClientContext context;
    v1::WatchRunRequest request;
    request.set_run_id(run.id());
    auto reader = stub_->WatchRun(&context, request);
    for (v1::RunEvent e; reader->Read(&e);) {
      if (e.has_state())
        final_state = e.state().state();
      else
        events.push_back(e);
    }
    ASSERT_TRUE(reader->Finish().ok());
  }
  ASSERT_EQ(final_state, v1::RUN_STATE_SUCCEEDED);
  std::vector<v1::Breakup> breakups;
  std::uint64_t breakup_seq = 0;
  for (std::size_t i = 0; i < events.size(); ++i) {
    EXPECT_EQ(events[i].seq(), i + 1);
    if (events[i].has_breakup()) {
      breakups.push_back(events[i].breakup());
      breakup_seq = events[i].seq();
    }
  }
  ASSERT_EQ(breakups.size(), 1u);
  const v1::Breakup& b = breakups[0];
  EXPECT_EQ(b.breakup_id(), 1u);
  EXPECT_EQ(b.kind(), v1::BREAKUP_KIND_EXPLOSION);
  EXPECT_EQ(b.source(), v1::BREAKUP_SOURCE_SCHEDULED);
  ASSERT_EQ(b.parents_size(), 1);
  EXPECT_EQ(b.parents(0), target_);
  ASSERT_GT(b.fragment_count(), 0u);
  EXPECT_EQ(b.first_id(), kFirstFragmentId);
  EXPECT_EQ(b.last_id(), b.first_id() + b.fragment_count() - 1);

  // Replay from the store after the breakup's predecessor: the breakup comes first, once.
  {
    grpc::ClientContext context;
    v1::WatchRunRequest request;
    request.set_run_id(run.id());
    request.set_after_seq(breakup_seq - 1);
    request.set_no_progress(true);
    auto reader = stub_->WatchRun(&context, request);
    std::vector<v1::RunEvent> replay;
    for (v1::RunEvent e; reader->Read(&e);)
      if (!e.has_state()) replay.push_back(e);
    ASSERT_TRUE(reader->Finish().ok());
    ASSERT_FALSE(replay.empty());
    EXPECT_EQ(replay.front().SerializeAsString(), events[breakup_seq - 1].SerializeAsString());
  }

  // ListFragments in pages: fragment_count rows, first_id..last_id in order.
  std::vector<v1::Fragment> fragments;
  v1::ListFragmentsRequest list;
  list.set_run_id(run.id());
  list.set_breakup_id(1);
  list.set_page_size(50);
  for (;;) {
    grpc::ClientContext context;
    v1::ListFragmentsResponse response;
    ASSERT_TRUE(stub_->ListFragments(&context, list, &response).ok());
    EXPECT_EQ(response.total(), b.fragment_count());
    fragments.insert(fragments.end(), response.fragments().begin(), response.fragments().end());
    if (response.next_page_token().empty()) break;
    list.set_page_token(response.next_page_token());
  }
  ASSERT_EQ(fragments.size(), b.fragment_count());
  double mass = 0;
  for (std::size_t i = 0; i < fragments.size(); ++i) {
    EXPECT_EQ(fragments[i].id(), b.first_id() + i);
    EXPECT_EQ(fragments[i].parent_id(), target_);
    EXPECT_GT(fragments[i].characteristic_length_m(), 0.0);
    mass += fragments[i].mass_kg();
  }
  EXPECT_NEAR(mass, b.fragment_mass_kg(), 1e-6 * b.fragment_mass_kg());

  // Stats: the breakup counted, fragments among the objects alive by type after it.
  {
    grpc::ClientContext context;
    v1::GetRunStatsRequest request;
    request.set_run_id(run.id());
    v1::RunStats stats;
    ASSERT_TRUE(stub_->GetRunStats(&context, request, &stats).ok());
    EXPECT_EQ(stats.breakups(), 1u);
    EXPECT_EQ(stats.fragments(), b.fragment_count());
    ASSERT_GT(stats.objects_alive_size(), 0);
    const v1::AliveSample& last = stats.objects_alive(stats.objects_alive_size() - 1);
    const v1::ObjectCounts& t = last.by_type();
    EXPECT_GT(t.fragments(), 0u);
    EXPECT_EQ(t.payload() + t.rocket_body() + t.debris() + t.unknown() + t.fragments(), last.objects_alive());
  }

  // Refusals: an unknown run, a page token not from a page.
  {
    grpc::ClientContext context;
    v1::ListFragmentsRequest request;
    request.set_run_id(run.id() + 100);
    v1::ListFragmentsResponse response;
    EXPECT_EQ(stub_->ListFragments(&context, request, &response).error_code(), grpc::StatusCode::NOT_FOUND);
  }
  for (const char* token : {"-1", "garbage"}) {
    grpc::ClientContext context;
    v1::ListFragmentsRequest request;
    request.set_run_id(run.id());
    request.set_page_token(token);
    v1::ListFragmentsResponse response;
    EXPECT_EQ(stub_->ListFragments(&context, request, &response).error_code(),
              grpc::StatusCode::INVALID_ARGUMENT)
        << token;
  }

  // The CLI: the breakup's JSON line in watch, its row in the table, the fragments in every format.
  const std::string id = std::to_string(run.id());
  const std::string server = " --server " + address_;
  auto watch = cli(dir_, "watch " + id + " --events all --output json" + server);
  ASSERT_EQ(watch.exit_code, 0) << watch.err;
  std::string breakup_line;
  for (const auto& line : lines_of(watch.out))
    if (line.find("\"type\":\"breakup\"") != std::string::npos) breakup_line = line;
  ASSERT_FALSE(breakup_line.empty()) << watch.out.substr(0, 2000);
  EXPECT_NE(breakup_line.find("\"parents\":[" + std::to_string(target_) + "]"), std::string::npos)
      << breakup_line;
  EXPECT_NE(breakup_line.find("\"fragments\":" + std::to_string(b.fragment_count()) + ","), std::string::npos)
      << breakup_line;
  EXPECT_NE(breakup_line.find("\"kind\":\"explosion\""), std::string::npos) << breakup_line;
  EXPECT_NE(breakup_line.find("\"seq\":" + std::to_string(breakup_seq) + ","), std::string::npos)
      << breakup_line;

  auto table = cli(dir_, "watch " + id + " --events all" + server);
  ASSERT_EQ(table.exit_code, 0) << table.err;
  EXPECT_NE(table.out.find("breakup"), std::string::npos);
  EXPECT_NE(table.out.find(std::to_string(b.fragment_count()) + " fragments"), std::string::npos)
      << table.out;

  auto csv = cli(dir_, "fragments " + id + " --output csv" + server);
  ASSERT_EQ(csv.exit_code, 0) << csv.err;
  auto rows = lines_of(csv.out);
  ASSERT_EQ(rows.size(), b.fragment_count() + 1);
  EXPECT_EQ(rows[0],
            "id,breakup_id,parent_id,characteristic_length_m,area_to_mass_m2_kg,mass_kg,delta_v_m_s");
  EXPECT_EQ(rows[1].rfind(std::to_string(kFirstFragmentId) + ",1," + std::to_string(target_) + ",", 0), 0u)
      << rows[1];

  auto json = cli(dir_, "fragments " + id + " --breakup 1 --limit 3 --output json" + server);
  ASSERT_EQ(json.exit_code, 0) << json.err;
  EXPECT_EQ(lines_of(json.out).size(), 3u);
  EXPECT_NE(json.out.find("\"parent_id\": " + std::to_string(target_)), std::string::npos) << json.out;

  auto listing = cli(dir_, "fragments " + id + server);
  ASSERT_EQ(listing.exit_code, 0) << listing.err;
  EXPECT_NE(listing.out.find("FRAGMENT " + std::to_string(kFirstFragmentId)), std::string::npos);
  EXPECT_NE(listing.out.find(std::to_string(b.fragment_count()) + " fragments"), std::string::npos);

  auto none = cli(dir_, "fragments " + id + " --breakup 7" + server);
  EXPECT_EQ(none.exit_code, 0);
  EXPECT_NE(none.out.find("no fragments"), std::string::npos);

  auto missing = cli(dir_, "fragments " + std::to_string(run.id() + 100) + server);
  EXPECT_EQ(missing.exit_code, 1);
  EXPECT_NE(missing.err.find("NOT_FOUND"), std::string::npos) << missing.err;

  auto show = cli(dir_, "show " + id + server);
  ASSERT_EQ(show.exit_code, 0) << show.err;
  EXPECT_NE(show.out.find("objects alive by type"), std::string::npos);
  EXPECT_NE(show.out.find("1 breakups"), std::string::npos) << show.out;

  // Deleting the run removes its fragments.
  {
    grpc::ClientContext context;
    v1::DeleteRunRequest request;
    request.set_run_id(run.id());
    v1::DeleteRunResponse response;
    ASSERT_TRUE(stub_->DeleteRun(&context, request, &response).ok());
  }
  EXPECT_EQ(manager_->store().list_fragments(list).total, 0u);
}

}  // namespace
}  // namespace kessler
