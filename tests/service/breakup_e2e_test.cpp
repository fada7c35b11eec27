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
#include "tests/service/in_process_service.hpp"
#include "tests/service/service_harness.hpp"

namespace kessler {
namespace {

using test::cli;

const char* const kBreakupScenario = R"yaml(
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

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream s(text);
  for (std::string line; std::getline(s, line);)
    if (!line.empty()) out.push_back(line);
  return out;
}

// One daemon and one run with the explosion, shared by the tests below (the run takes a second).
class BreakupEndToEnd : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { shared_ = new Shared(test::parsed_scenario(kBreakupScenario)); }
  static void TearDownTestSuite() {
    delete shared_;
    shared_ = nullptr;
  }

  struct Shared : test::InProcessService {
    explicit Shared(const v1::Scenario& parsed)
        : InProcessService(test::explode_at(test::first_object(parsed), kExplosionStep)), scenario(parsed) {
      run = submit(scenario);
      events = watch(run.id(), 0, false, &final_state);
    }
    v1::Scenario scenario;
    ObjectId target = test::first_object(scenario);  // the one that explodes
    v1::Run run;
    std::vector<v1::RunEvent> events;
    v1::RunState final_state = v1::RUN_STATE_UNSPECIFIED;
  };

  // The run's one breakup event (fails the test when there is not exactly one).
  static const v1::RunEvent* breakup_event() {
    const v1::RunEvent* found = nullptr;
    int n = 0;
    for (const auto& e : shared_->events)
      if (e.has_breakup()) {
        found = &e;
        ++n;
      }
    EXPECT_EQ(n, 1);
    return found;
  }
  static std::string server_option() { return " --server " + shared_->address; }
  static std::string run_id() { return std::to_string(shared_->run.id()); }

  static Shared* shared_;
};

BreakupEndToEnd::Shared* BreakupEndToEnd::shared_ = nullptr;

TEST_F(BreakupEndToEnd, WatchStreamsTheBreakupInSequenceAndReplaysItOnce) {
  ASSERT_EQ(shared_->final_state, v1::RUN_STATE_SUCCEEDED);
  const auto& events = shared_->events;
  for (std::size_t i = 0; i < events.size(); ++i) EXPECT_EQ(events[i].seq(), i + 1);
  const v1::RunEvent* e = breakup_event();
  ASSERT_TRUE(e);
  const v1::Breakup& b = e->breakup();
  EXPECT_EQ(b.breakup_id(), 1u);
  EXPECT_EQ(b.kind(), v1::BREAKUP_KIND_EXPLOSION);
  EXPECT_EQ(b.source(), v1::BREAKUP_SOURCE_SCHEDULED);
  ASSERT_EQ(b.parents_size(), 1);
  EXPECT_EQ(b.parents(0), shared_->target);
  ASSERT_GT(b.fragment_count(), 0u);
  EXPECT_EQ(b.first_id(), kFirstFragmentId);
  EXPECT_EQ(b.last_id(), b.first_id() + b.fragment_count() - 1);
  // Replayed from the store after its predecessor: the breakup comes first, the same bytes, once.
  auto replay = shared_->watch(shared_->run.id(), e->seq() - 1, true);
  ASSERT_FALSE(replay.empty());
  EXPECT_EQ(replay.front().SerializeAsString(), e->SerializeAsString());
  for (std::size_t i = 1; i < replay.size(); ++i) EXPECT_FALSE(replay[i].has_breakup());
}

TEST_F(BreakupEndToEnd, ListFragmentsPagesThroughTheBreakupsFragments) {
  const v1::RunEvent* e = breakup_event();
  ASSERT_TRUE(e);
  const v1::Breakup& b = e->breakup();
  std::vector<v1::Fragment> fragments;
  v1::ListFragmentsRequest list;
  list.set_run_id(shared_->run.id());
  list.set_breakup_id(1);
  list.set_page_size(50);
  for (;;) {
    grpc::ClientContext context;
    v1::ListFragmentsResponse response;
    ASSERT_TRUE(shared_->stub->ListFragments(&context, list, &response).ok());
    EXPECT_EQ(response.total(), b.fragment_count());
    fragments.insert(fragments.end(), response.fragments().begin(), response.fragments().end());
    if (response.next_page_token().empty()) break;
    list.set_page_token(response.next_page_token());
  }
  ASSERT_EQ(fragments.size(), b.fragment_count());
  double mass = 0;
  for (std::size_t i = 0; i < fragments.size(); ++i) {
    EXPECT_EQ(fragments[i].id(), b.first_id() + i);
    EXPECT_EQ(fragments[i].parent_id(), shared_->target);
    EXPECT_GT(fragments[i].characteristic_length_m(), 0.0);
    mass += fragments[i].mass_kg();
  }
  EXPECT_NEAR(mass, b.fragment_mass_kg(), 1e-6 * b.fragment_mass_kg());
}

TEST_F(BreakupEndToEnd, StatsCountTheBreakupAndObjectsByType) {
  const v1::RunEvent* e = breakup_event();
  ASSERT_TRUE(e);
  grpc::ClientContext context;
  v1::GetRunStatsRequest request;
  request.set_run_id(shared_->run.id());
  v1::RunStats stats;
  ASSERT_TRUE(shared_->stub->GetRunStats(&context, request, &stats).ok());
  EXPECT_EQ(stats.breakups(), 1u);
  EXPECT_EQ(stats.fragments(), e->breakup().fragment_count());
  ASSERT_GT(stats.objects_alive_size(), 0);
  const v1::AliveSample& last = stats.objects_alive(stats.objects_alive_size() - 1);
  const v1::ObjectCounts& t = last.by_type();
  EXPECT_GT(t.fragments(), 0u);
  EXPECT_EQ(t.payload() + t.rocket_body() + t.debris() + t.unknown() + t.fragments(), last.objects_alive());
  EXPECT_EQ(stats.objects_alive(0).by_type().fragments(), 0u);
}

TEST_F(BreakupEndToEnd, ListFragmentsRefusesAnUnknownRunAndBadPageTokens) {
  {
    grpc::ClientContext context;
    v1::ListFragmentsRequest request;
    request.set_run_id(shared_->run.id() + 100);
    v1::ListFragmentsResponse response;
    EXPECT_EQ(shared_->stub->ListFragments(&context, request, &response).error_code(),
              grpc::StatusCode::NOT_FOUND);
  }
  for (const char* token : {"-1", "garbage"}) {
    grpc::ClientContext context;
    v1::ListFragmentsRequest request;
    request.set_run_id(shared_->run.id());
    request.set_page_token(token);
    v1::ListFragmentsResponse response;
    EXPECT_EQ(shared_->stub->ListFragments(&context, request, &response).error_code(),
              grpc::StatusCode::INVALID_ARGUMENT)
        << token;
  }
  auto missing = cli(shared_->dir, "fragments " + std::to_string(shared_->run.id() + 100) + server_option());
  EXPECT_EQ(missing.exit_code, 1);
  EXPECT_NE(missing.err.find("NOT_FOUND"), std::string::npos) << missing.err;
}

TEST_F(BreakupEndToEnd, WatchPrintsTheBreakupAsAJsonLineAndATableRow) {
  const v1::RunEvent* e = breakup_event();
  ASSERT_TRUE(e);
  const v1::Breakup& b = e->breakup();
  auto watch = cli(shared_->dir, "watch " + run_id() + " --events all --output json" + server_option());
  ASSERT_EQ(watch.exit_code, 0) << watch.err;
  std::string line;
  for (const auto& l : lines_of(watch.out))
    if (l.find("\"type\":\"breakup\"") != std::string::npos) line = l;
  ASSERT_FALSE(line.empty()) << watch.out.substr(0, 2000);
  EXPECT_NE(line.find("\"parents\":[" + std::to_string(shared_->target) + "]"), std::string::npos) << line;
  EXPECT_NE(line.find("\"fragments\":" + std::to_string(b.fragment_count()) + ","), std::string::npos)
      << line;
  EXPECT_NE(line.find("\"kind\":\"explosion\""), std::string::npos) << line;
  EXPECT_NE(line.find("\"source\":\"scheduled\""), std::string::npos) << line;
  EXPECT_NE(line.find("\"seq\":" + std::to_string(e->seq()) + ","), std::string::npos) << line;
  EXPECT_NE(line.find("\"first_id\":" + std::to_string(b.first_id()) + ","), std::string::npos) << line;

  auto table = cli(shared_->dir, "watch " + run_id() + server_option());  // notable events
  ASSERT_EQ(table.exit_code, 0) << table.err;
  EXPECT_NE(table.out.find("breakup"), std::string::npos) << table.out;
  EXPECT_NE(table.out.find(std::to_string(b.fragment_count()) + " fragments"), std::string::npos)
      << table.out;
}

TEST_F(BreakupEndToEnd, FragmentsCommandListsThemInEveryFormat) {
  const v1::RunEvent* e = breakup_event();
  ASSERT_TRUE(e);
  const std::uint64_t count = e->breakup().fragment_count();
  const std::string target = std::to_string(shared_->target);
  auto csv = cli(shared_->dir, "fragments " + run_id() + " --output csv" + server_option());
  ASSERT_EQ(csv.exit_code, 0) << csv.err;
  auto rows = lines_of(csv.out);
  ASSERT_EQ(rows.size(), count + 1);
  EXPECT_EQ(rows[0],
            "id,breakup_id,parent_id,characteristic_length_m,area_to_mass_m2_kg,mass_kg,delta_v_m_s");
  EXPECT_EQ(rows[1].rfind(std::to_string(kFirstFragmentId) + ",1," + target + ",", 0), 0u) << rows[1];

  auto json =
      cli(shared_->dir, "fragments " + run_id() + " --breakup 1 --limit 3 --output json" + server_option());
  ASSERT_EQ(json.exit_code, 0) << json.err;
  EXPECT_EQ(lines_of(json.out).size(), 3u);
  EXPECT_NE(json.out.find("\"parent_id\": " + target), std::string::npos) << json.out;

  auto listing = cli(shared_->dir, "fragments " + run_id() + server_option());
  ASSERT_EQ(listing.exit_code, 0) << listing.err;
  EXPECT_NE(listing.out.find("FRAGMENT " + std::to_string(kFirstFragmentId)), std::string::npos);
  EXPECT_NE(listing.out.find(std::to_string(count) + " fragments"), std::string::npos);

  auto none = cli(shared_->dir, "fragments " + run_id() + " --breakup 7" + server_option());
  EXPECT_EQ(none.exit_code, 0);
  EXPECT_NE(none.out.find("no fragments"), std::string::npos);

  auto show = cli(shared_->dir, "show " + run_id() + server_option());
  ASSERT_EQ(show.exit_code, 0) << show.err;
  EXPECT_NE(show.out.find("objects alive by type"), std::string::npos);
  EXPECT_NE(show.out.find("1 breakups (" + std::to_string(count) + " fragments)"), std::string::npos)
      << show.out;
}

// Last (gtest runs a suite's tests in order): deleting the run removes its fragments.
TEST_F(BreakupEndToEnd, ZDeleteRemovesTheFragments) {
  {
    grpc::ClientContext context;
    v1::DeleteRunRequest request;
    request.set_run_id(shared_->run.id());
    v1::DeleteRunResponse response;
    ASSERT_TRUE(shared_->stub->DeleteRun(&context, request, &response).ok());
  }
  v1::ListFragmentsRequest request;
  request.set_run_id(shared_->run.id());
  EXPECT_EQ(shared_->manager->store().list_fragments(request).total, 0u);
}

}  // namespace
}  // namespace kessler
