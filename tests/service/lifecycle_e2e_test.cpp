// Launches and lifecycles end to end: a run whose scenario has traffic (an inline plan with a short-lived
// mission) on a daemon in this process, its gRPC API on loopback and the real kessler binary: WatchRun
// streams the lifecycle events in sequence, GetRunStats counts them, the CLI prints them as JSON lines
// and table rows and `show` counts them.
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

// 12 satellites launched 00:05..00:15 in two planes; 4 at 00:01 whose lifetime (0.00002 years, 631 s)
// ends at about 00:12, then disposal (half succeed).
const char* const kLifecycleScenario = R"yaml(
name: lifecycle-e2e
start_epoch: "2022-01-01T00:00:00Z"
duration_days: 0.02
dt_s: 30
population: {synthetic: {objects: 200}}
conjunctions: {screening_distance_km: 5}
progress_every_steps: 10
traffic:
  enabled: true
  launch_plan_csv: |
    label,epoch,epoch_end,count,altitude_km,inclination_deg,planes,lifetime_years
    shell,2022-01-01T00:05:00Z,2022-01-01T00:15:00Z,12,550,53,2,5
    short,2022-01-01T00:01:00Z,,4,520,97.5,1,0.00002
  disposal: {success_probability: 0.5, target_lifetime_years: 5}
seed: 3
)yaml";

class LifecycleEndToEnd : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { shared_ = new Shared(); }
  static void TearDownTestSuite() {
    delete shared_;
    shared_ = nullptr;
  }

  struct Shared : test::InProcessService {
    Shared() {
      if (parse_scenario(kLifecycleScenario, scenario)) throw std::runtime_error("scenario");
      run = submit(scenario);
      events = watch(run.id(), 0, false, &final_state);
    }
    v1::Scenario scenario;
    v1::Run run;
    std::vector<v1::RunEvent> events;
    v1::RunState final_state = v1::RUN_STATE_UNSPECIFIED;
  };

  static std::string server_option() { return " --server " + shared_->address; }
  static std::string run_id() { return std::to_string(shared_->run.id()); }
  static Shared* shared_;
};

LifecycleEndToEnd::Shared* LifecycleEndToEnd::shared_ = nullptr;

TEST_F(LifecycleEndToEnd, WatchStreamsLaunchesEndsOfLifeAndDisposalsInSequence) {
  ASSERT_EQ(shared_->final_state, v1::RUN_STATE_SUCCEEDED);
  std::uint64_t launched = 0, ends = 0, outcomes = 0;
  ObjectId next = kFirstLaunchId;
  const auto& events = shared_->events;
  for (std::size_t i = 0; i < events.size(); ++i) {
    EXPECT_EQ(events[i].seq(), i + 1);
    if (!events[i].has_lifecycle()) continue;
    const v1::Lifecycle& l = events[i].lifecycle();
    switch (l.kind()) {
      case v1::LIFECYCLE_KIND_LAUNCH:
        EXPECT_EQ(l.first_id(), next);
        launched += l.last_id() - l.first_id() + 1;
        next = l.last_id() + 1;
        break;
      case v1::LIFECYCLE_KIND_END_OF_LIFE:
        ++ends;
        EXPECT_GE(l.time_s(), 60.0 + 631.0);
        break;
      default:
        ++outcomes;
        EXPECT_EQ(l.first_id(), l.last_id());
    }
  }
  EXPECT_EQ(launched, 16u);
  EXPECT_EQ(ends, 4u);
  EXPECT_EQ(outcomes, 4u);
}

TEST_F(LifecycleEndToEnd, StatsCountTheLifecycleEvents) {
  grpc::ClientContext context;
  v1::GetRunStatsRequest request;
  request.set_run_id(shared_->run.id());
  v1::RunStats stats;
  ASSERT_TRUE(shared_->stub->GetRunStats(&context, request, &stats).ok());
  EXPECT_GE(stats.launches(), 2u);
  EXPECT_EQ(stats.launched_objects(), 16u);
  EXPECT_EQ(stats.ends_of_life(), 4u);
  EXPECT_EQ(stats.disposals() + stats.disposals_failed() + stats.deorbits(), 4u);
  EXPECT_EQ(stats.deorbits(), 0u);
}

TEST_F(LifecycleEndToEnd, TheCliPrintsThemAsJsonLinesTableRowsAndCounts) {
  auto json = cli(shared_->dir, "watch " + run_id() + " --events all --output json" + server_option());
  ASSERT_EQ(json.exit_code, 0) << json.err;
  EXPECT_NE(json.out.find("{\"type\":\"launch\",\"seq\":"), std::string::npos) << json.out.substr(0, 2000);
  EXPECT_NE(json.out.find("\"first_id\":" + std::to_string(kFirstLaunchId) + ","), std::string::npos);
  EXPECT_NE(json.out.find("{\"type\":\"end_of_life\",\"seq\":"), std::string::npos);

  auto table = cli(shared_->dir, "watch " + run_id() + " --events all" + server_option());
  ASSERT_EQ(table.exit_code, 0) << table.err;
  EXPECT_NE(table.out.find("launch"), std::string::npos) << table.out;
  EXPECT_NE(table.out.find("end_of_life"), std::string::npos) << table.out;

  auto show = cli(shared_->dir, "show " + run_id() + server_option());
  ASSERT_EQ(show.exit_code, 0) << show.err;
  EXPECT_NE(show.out.find("traffic: 16 objects launched"), std::string::npos) << show.out;
  EXPECT_NE(show.out.find("4 ends of life"), std::string::npos) << show.out;
}

}  // namespace
}  // namespace kessler
