// Monte Carlo ensembles end to end: a daemon in this process, its gRPC API on loopback and the real
// kessler binary. One ensemble of a synthetic population (the seed draws its orbits) is shared by the
// tests: its members get seeds seed..seed+N-1 and identical scenarios otherwise, differ from each
// other, equal a standalone run of their seed, and the daemon's aggregates equal those recomputed here
// from the members' stored results (GetRunStats, ListConjunctions). Then bad input, and the CLI.
#include <grpcpp/grpcpp.h>
#include <gtest/gtest.h>

#include <google/protobuf/struct.pb.h>
#include <google/protobuf/util/json_util.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>
#include <thread>

#include "core/scenario/run_builder.hpp"
#include "kessler/v1/service.grpc.pb.h"
#include "server/api_server.hpp"
#include "server/ensembles.hpp"
#include "server/run_manager.hpp"
#include "tests/service/in_process_service.hpp"
#include "tests/service/service_harness.hpp"

namespace kessler {
namespace {

using test::cli;

const char* const kEnsembleScenario = R"yaml(
name: ensemble-e2e
duration_days: 0.004
dt_s: 10
population:
  synthetic:
    objects: 300
    min_altitude_km: 500
    max_altitude_km: 700
conjunctions:
  screening_distance_km: 40
progress_every_steps: 5
seed: 40
ensemble:
  members: 3
)yaml";

constexpr std::uint64_t kMembers = 3;
constexpr std::uint64_t kSeed = 40;

class EnsembleEndToEnd : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { shared_ = new Shared(); }
  static void TearDownTestSuite() {
    delete shared_;
    shared_ = nullptr;
  }

  struct Shared : test::InProcessService {
    Shared()
        : InProcessService([](server::ManagerOptions& options) {
            options.runs_at_once = 2;
            options.threads_per_run = 1;
          }) {
      if (parse_scenario(kEnsembleScenario, scenario)) throw std::runtime_error("scenario");
      v1::SubmitEnsembleRequest submit;
      *submit.mutable_scenario() = scenario;
      grpc::ClientContext context;
      auto status = stub->SubmitEnsemble(&context, submit, &submitted);
      if (!status.ok()) throw std::runtime_error("submit: " + status.error_message());
      ensemble = wait_for(submitted.id());
    }
    // GetEnsemble once every member has ended.
    v1::EnsembleReport wait_for(std::int64_t id) {
      for (int i = 0; i < 1200; ++i) {
        v1::EnsembleReport e = get(id);
        if (server::is_terminal(e.state())) return e;
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
      }
      throw std::runtime_error("the ensemble did not end");
    }
    v1::EnsembleReport get(std::int64_t id, const std::vector<double>& kappas = {}) {
      grpc::ClientContext context;
      v1::GetEnsembleRequest request;
      request.set_ensemble_id(id);
      for (double k : kappas) request.add_kappas(k);
      v1::EnsembleReport out;
      if (!stub->GetEnsemble(&context, request, &out).ok()) throw std::runtime_error("get ensemble");
      return out;
    }
    v1::Run run(std::int64_t id) {
      grpc::ClientContext context;
      v1::GetRunRequest request;
      request.set_run_id(id);
      v1::Run out;
      if (!stub->GetRun(&context, request, &out).ok()) throw std::runtime_error("get run");
      return out;
    }

    v1::Scenario scenario;
    v1::EnsembleReport submitted, ensemble;
  };
  static Shared* shared_;
};

EnsembleEndToEnd::Shared* EnsembleEndToEnd::shared_ = nullptr;

TEST_F(EnsembleEndToEnd, MembersDifferOnlyInTheirSeed) {
  const auto& e = shared_->ensemble;
  EXPECT_EQ(e.state(), v1::RUN_STATE_SUCCEEDED);
  EXPECT_EQ(e.members(), kMembers);
  EXPECT_EQ(e.finished(), kMembers);
  EXPECT_EQ(e.aggregated(), kMembers);
  EXPECT_EQ(e.base_seed(), kSeed);
  ASSERT_EQ(e.member_size(), static_cast<int>(kMembers));
  v1::Scenario expected = shared_->scenario;
  expected.clear_ensemble();
  expected.clear_seed();
  for (std::uint64_t k = 0; k < kMembers; ++k) {
    const auto& m = e.member(static_cast<int>(k));
    EXPECT_EQ(m.member_index(), k);
    EXPECT_EQ(m.seed(), kSeed + k);
    v1::Run run = shared_->run(m.run_id());
    EXPECT_EQ(run.ensemble_id(), e.id());
    EXPECT_EQ(run.member_index(), k);
    EXPECT_EQ(run.state(), v1::RUN_STATE_SUCCEEDED);
    EXPECT_EQ(run.scenario().seed(), kSeed + k);
    v1::Scenario rest = run.scenario();
    rest.clear_seed();
    EXPECT_EQ(rest.SerializeAsString(), expected.SerializeAsString()) << "member " << k;
  }
  // The seed draws the synthetic orbits: the members' events differ.
  EXPECT_NE(e.member(0).events_digest(), e.member(1).events_digest());
  EXPECT_NE(e.member(1).events_digest(), e.member(2).events_digest());
}

TEST_F(EnsembleEndToEnd, AMemberEqualsAStandaloneRunOfItsSeed) {
  v1::SubmitRunRequest submit;
  *submit.mutable_scenario() = shared_->scenario;
  submit.mutable_scenario()->clear_ensemble();
  submit.mutable_scenario()->set_seed(kSeed + 1);
  v1::Run run;
  {
    grpc::ClientContext context;
    ASSERT_TRUE(shared_->stub->SubmitRun(&context, submit, &run).ok());
  }
  EXPECT_EQ(run.ensemble_id(), 0);
  for (int i = 0; i < 1200 && !server::is_terminal(run.state()); ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    run = shared_->run(run.id());
  }
  ASSERT_EQ(run.state(), v1::RUN_STATE_SUCCEEDED);
  EXPECT_EQ(run.summary().events_digest(), shared_->ensemble.member(1).events_digest());
}

// The members' stored results as the API gives them.
struct Recomputed {
  std::vector<std::vector<v1::AliveSample>> alive;
  std::vector<std::vector<double>> collisions;
  std::vector<std::vector<std::vector<double>>> conjunctions;  // member, kappa
};

Recomputed recompute(v1::KesslerService::Stub& stub, const v1::EnsembleReport& e) {
  Recomputed r;
  for (const auto& m : e.member()) {
    grpc::ClientContext context;
    v1::GetRunStatsRequest request;
    request.set_run_id(m.run_id());
    v1::RunStats stats;
    if (!stub.GetRunStats(&context, request, &stats).ok()) throw std::runtime_error("stats");
    r.alive.emplace_back(stats.objects_alive().begin(), stats.objects_alive().end());
    auto list = [&](bool collisions_only, std::optional<double> kappa_max) {
      grpc::ClientContext c;
      v1::ListConjunctionsRequest q;
      q.set_run_id(m.run_id());
      q.set_collisions_only(collisions_only);
      if (kappa_max) q.set_kappa_max(*kappa_max);
      q.set_page_size(100000);
      v1::ListConjunctionsResponse out;
      if (!stub.ListConjunctions(&c, q, &out).ok()) throw std::runtime_error("conjunctions");
      std::vector<double> times;
      for (const auto& x : out.conjunctions()) times.push_back(x.tca_s());
      return times;
    };
    r.collisions.push_back(list(true, std::nullopt));
    r.conjunctions.emplace_back();
    for (double k : e.kappas()) r.conjunctions.back().push_back(list(false, k));
  }
  return r;
}

double mean_count_until(const std::vector<std::vector<double>>& per_member, double t) {
  double sum = 0;
  for (const auto& times : per_member)
    sum += static_cast<double>(std::count_if(times.begin(), times.end(), [&](double x) { return x <= t; }));
  return sum / static_cast<double>(per_member.size());
}

TEST_F(EnsembleEndToEnd, AggregatesEqualThoseRecomputedFromTheMembers) {
  EXPECT_EQ(std::vector<double>(shared_->ensemble.kappas().begin(), shared_->ensemble.kappas().end()),
            (std::vector<double>{1, 2, 5, 10}));
  // The scenario screens by distance (40 km): its kappas are in the thousands. The last band takes all.
  const v1::EnsembleReport e = shared_->get(shared_->ensemble.id(), {1e6, 10, 1e4, 1e3});
  ASSERT_EQ(std::vector<double>(e.kappas().begin(), e.kappas().end()),
            (std::vector<double>{10, 1e3, 1e4, 1e6}));
  const Recomputed r = recompute(*shared_->stub, e);
  // The members share their progress times (one scenario): every sample of member 0 is in the series.
  ASSERT_EQ(static_cast<std::size_t>(e.series_size()), r.alive[0].size());
  double total_conjunctions = 0;
  for (int i = 0; i < e.series_size(); ++i) {
    const v1::EnsembleSample& s = e.series(i);
    std::vector<double> objects;
    double debris = 0;
    for (const auto& member : r.alive) {
      ASSERT_EQ(member[static_cast<std::size_t>(i)].sim_time_s(), s.t());
      objects.push_back(static_cast<double>(member[static_cast<std::size_t>(i)].objects_alive()));
      debris += static_cast<double>(member[static_cast<std::size_t>(i)].by_type().debris());
    }
    std::sort(objects.begin(), objects.end());
    // Three members: p05 at h = 0.1, p95 at h = 1.9, the median the middle one.
    const double mean = (objects[0] + objects[1] + objects[2]) / 3.0;
    EXPECT_NEAR(s.objects_mean(), mean, 1e-9);
    EXPECT_NEAR(s.objects_median(), objects[1], 1e-9);
    EXPECT_NEAR(s.objects_p05(), objects[0] + 0.1 * (objects[1] - objects[0]), 1e-9);
    EXPECT_NEAR(s.objects_p95(), objects[1] + 0.9 * (objects[2] - objects[1]), 1e-9);
    EXPECT_NEAR(s.debris_mean(), debris / 3.0, 1e-9);
    EXPECT_NEAR(s.collisions_mean(), mean_count_until(r.collisions, s.t()), 1e-9);
    ASSERT_EQ(s.conjunctions_mean_size(), 4);
    for (int k = 0; k < 4; ++k) {
      std::vector<std::vector<double>> band;
      for (const auto& member : r.conjunctions) band.push_back(member[static_cast<std::size_t>(k)]);
      EXPECT_NEAR(s.conjunctions_mean(k), mean_count_until(band, s.t()), 1e-9) << "kappa " << e.kappas(k);
      std::vector<double> counts;
      for (const auto& times : band) counts.push_back(mean_count_until({times}, s.t()));
      std::sort(counts.begin(), counts.end());
      ASSERT_EQ(s.conjunctions_p05_size(), 4);
      ASSERT_EQ(s.conjunctions_p95_size(), 4);
      EXPECT_NEAR(s.conjunctions_p05(k), counts[0] + 0.1 * (counts[1] - counts[0]), 1e-9)
          << "kappa " << e.kappas(k);
      EXPECT_NEAR(s.conjunctions_p95(k), counts[1] + 0.9 * (counts[2] - counts[1]), 1e-9)
          << "kappa " << e.kappas(k);
    }
    total_conjunctions = s.conjunctions_mean(3);
  }
  EXPECT_GT(total_conjunctions, 0) << "the scenario should find conjunctions";
}

TEST_F(EnsembleEndToEnd, BadRequestsAreRefused) {
  auto submit = [&](const std::string& text, std::uint64_t members) {
    v1::SubmitEnsembleRequest request;
    request.set_scenario_text(text);
    request.set_members(members);
    v1::EnsembleReport out;
    grpc::ClientContext context;
    return shared_->stub->SubmitEnsemble(&context, request, &out);
  };
  const std::string plain = "population: {synthetic: {objects: 10}}\nduration_days: 0.001\n";
  auto zero = submit(plain + "ensemble: {members: 0}\n", 0);
  EXPECT_EQ(zero.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_EQ(zero.error_message(), "ensemble.members: must be in 1..1000, got 0");
  auto none = submit(plain, 0);
  EXPECT_EQ(none.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  auto above = submit(plain, 1001);
  EXPECT_EQ(above.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_EQ(above.error_message(), "ensemble.members: must be in 1..1000, got 1001");
  auto bad_scenario = submit("population: {synthetic: {objects: 10}}\ndt_s: -1\n", 2);
  EXPECT_EQ(bad_scenario.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  {
    v1::SubmitRunRequest request;
    request.set_scenario_text(plain + "ensemble: {members: 2}\n");
    v1::Run out;
    grpc::ClientContext context;
    auto status = shared_->stub->SubmitRun(&context, request, &out);
    EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
    EXPECT_EQ(status.error_message().rfind("ensemble:", 0), 0u) << status.error_message();
  }
  {
    v1::GetEnsembleRequest request;
    request.set_ensemble_id(999);
    v1::EnsembleReport out;
    grpc::ClientContext context;
    EXPECT_EQ(shared_->stub->GetEnsemble(&context, request, &out).error_code(), grpc::StatusCode::NOT_FOUND);
  }
  {
    v1::CancelEnsembleRequest request;
    request.set_ensemble_id(999);
    v1::EnsembleReport out;
    grpc::ClientContext context;
    EXPECT_EQ(shared_->stub->CancelEnsemble(&context, request, &out).error_code(),
              grpc::StatusCode::NOT_FOUND);
  }
  {
    v1::CancelEnsembleRequest request;
    request.set_ensemble_id(shared_->ensemble.id());
    v1::EnsembleReport out;
    grpc::ClientContext context;
    EXPECT_EQ(shared_->stub->CancelEnsemble(&context, request, &out).error_code(),
              grpc::StatusCode::FAILED_PRECONDITION);
  }
}

google::protobuf::Struct parse_json(const std::string& text) {
  google::protobuf::Struct out;
  auto status = google::protobuf::util::JsonStringToMessage(text, &out);
  if (!status.ok()) throw std::runtime_error("not JSON: " + text);
  return out;
}

TEST_F(EnsembleEndToEnd, CliShowsTheEnsemble) {
  const TempDir& dir = shared_->dir;
  const std::string server = " --server " + shared_->address;
  const std::string id = std::to_string(shared_->ensemble.id());
  auto show = cli(dir, "ensemble show " + id + " --output json" + server);
  ASSERT_EQ(show.exit_code, 0) << show.err;
  auto json = parse_json(show.last_line());
  EXPECT_EQ(json.fields().at("members").number_value(), 3);
  EXPECT_EQ(json.fields().at("finished").number_value(), 3);
  const auto& series = json.fields().at("series").list_value();
  ASSERT_EQ(series.values_size(), shared_->ensemble.series_size());
  for (int i = 0; i < series.values_size(); ++i) {
    const auto& sample = series.values(i).struct_value().fields();
    for (const char* key : {"t", "objects_mean", "objects_p05", "objects_p95", "collisions_mean",
                            "conjunctions_mean", "conjunctions_p05", "conjunctions_p95"})
      ASSERT_TRUE(sample.count(key)) << key;
    EXPECT_NEAR(sample.at("objects_mean").number_value(), shared_->ensemble.series(i).objects_mean(), 1e-6);
  }
  auto csv = cli(dir, "ensemble show " + id + " --output csv" + server);
  ASSERT_EQ(csv.exit_code, 0) << csv.err;
  EXPECT_EQ(std::count(csv.out.begin(), csv.out.end(), '\n'), shared_->ensemble.series_size() + 1);
  EXPECT_EQ(csv.out.rfind("t_s,objects_mean,objects_median,objects_p05,objects_p95,", 0), 0u) << csv.out;
  EXPECT_NE(csv.out.find(",conj_kappa_10_mean,conj_kappa_1_p05,"), std::string::npos) << csv.out;
  EXPECT_NE(csv.out.find(",conj_kappa_10_p95\n"), std::string::npos) << csv.out;
  auto table = cli(dir, "ensemble show " + id + server);
  EXPECT_EQ(table.exit_code, 0);
  EXPECT_NE(table.out.find("3/3 members finished"), std::string::npos) << table.out;
  auto list = cli(dir, "ensemble list --output json" + server);
  EXPECT_EQ(list.exit_code, 0);
  EXPECT_NE(list.out.find("\"ensemble_id\": " + id), std::string::npos) << list.out;
  auto member = cli(dir, "show " + std::to_string(shared_->ensemble.member(1).run_id()) + server);
  EXPECT_EQ(member.exit_code, 0) << member.err;
  EXPECT_NE(member.out.find("ensemble  " + id + ", member 1 (seed 41)"), std::string::npos) << member.out;
  auto bad_id = cli(dir, "ensemble show 0" + server);
  EXPECT_EQ(bad_id.exit_code, 2);
  EXPECT_NE(bad_id.err.find("must be an ensemble id"), std::string::npos) << bad_id.err;
  auto missing = cli(dir, "ensemble show 999" + server);
  EXPECT_EQ(missing.exit_code, 1);
  EXPECT_NE(missing.err.find("NOT_FOUND"), std::string::npos) << missing.err;
}

TEST_F(EnsembleEndToEnd, CliSubmitsAndCancelsAnEnsemble) {
  const TempDir& dir = shared_->dir;
  const std::string server = " --server " + shared_->address;
  const std::string file = dir.path() + "/long.yaml";
  test::write_text(file, "name: long\nduration_days: 2\npopulation: {synthetic: {objects: 200}}\n");
  auto above = cli(dir, "submit " + file + " --members 1001" + server);
  EXPECT_EQ(above.exit_code, 2);
  EXPECT_NE(above.err.find("ensemble.members: must be in 1..1000, got 1001"), std::string::npos) << above.err;
  auto zero = cli(dir, "submit " + file + " --members 0" + server);
  EXPECT_EQ(zero.exit_code, 2);
  auto submitted = cli(dir, "submit " + file + " --members 2 --output json" + server);
  ASSERT_EQ(submitted.exit_code, 0) << submitted.err;
  auto json = parse_json(submitted.last_line());
  ASSERT_TRUE(json.fields().count("ensemble_id")) << submitted.out;
  EXPECT_EQ(json.fields().at("members").number_value(), 2);
  const auto id = static_cast<std::int64_t>(json.fields().at("ensemble_id").number_value());
  auto cancelled = cli(dir, "ensemble cancel " + std::to_string(id) + " --output json" + server);
  EXPECT_EQ(cancelled.exit_code, 0) << cancelled.err;
  v1::EnsembleReport e = shared_->wait_for(id);
  EXPECT_EQ(e.state(), v1::RUN_STATE_CANCELLED);
  EXPECT_EQ(e.finished(), 2u);
  EXPECT_EQ(e.aggregated(), 0u);
  EXPECT_EQ(e.series_size(), 0);
}

// The percentile rule on a hand-made set: linear interpolation between order statistics.
TEST(EnsemblePercentile, LinearInterpolationBetweenOrderStatistics) {
  const std::vector<double> x = {1, 2, 4, 8, 16};  // h = 4p
  EXPECT_DOUBLE_EQ(server::percentile(x, 0.0), 1);
  EXPECT_DOUBLE_EQ(server::percentile(x, 0.5), 4);
  EXPECT_DOUBLE_EQ(server::percentile(x, 1.0), 16);
  EXPECT_DOUBLE_EQ(server::percentile(x, 0.05), 1.2);   // h = 0.2: 1 + 0.2 (2 - 1)
  EXPECT_DOUBLE_EQ(server::percentile(x, 0.95), 14.4);  // h = 3.8: 8 + 0.8 (16 - 8)
  EXPECT_DOUBLE_EQ(server::percentile(x, 0.25), 2);
  EXPECT_DOUBLE_EQ(server::percentile({7}, 0.05), 7);
  EXPECT_DOUBLE_EQ(server::percentile({3, 5}, 0.5), 4);
  EXPECT_DOUBLE_EQ(server::percentile({}, 0.5), 0);
}

TEST(EnsembleSeries, CommonTimesAndCumulativeMeans) {
  auto sample = [](double t, std::uint64_t n) {
    v1::AliveSample s;
    s.set_sim_time_s(t);
    s.set_objects_alive(n);
    s.mutable_by_type()->set_debris(n);
    return s;
  };
  server::MemberResults a, b;
  a.alive = {sample(0, 10), sample(10, 9), sample(20, 8)};
  b.alive = {sample(0, 12), sample(10, 11)};  // ended early: the series stops at 10
  a.collision_times = {5, 10};
  b.collision_times = {15};
  a.catastrophic_times = {10};
  a.conjunction_times = {{1, 2, 3}};
  b.conjunction_times = {{11}};
  auto series = server::aggregate_series({a, b});
  ASSERT_EQ(series.size(), 2u);
  EXPECT_EQ(series[0].t(), 0);
  EXPECT_DOUBLE_EQ(series[0].objects_mean(), 11);
  EXPECT_DOUBLE_EQ(series[0].collisions_mean(), 0);
  EXPECT_DOUBLE_EQ(series[1].objects_mean(), 10);
  EXPECT_DOUBLE_EQ(series[1].objects_p05(), 9.1);
  EXPECT_DOUBLE_EQ(series[1].debris_mean(), 10);
  EXPECT_DOUBLE_EQ(series[1].collisions_mean(), 1);  // a: 2 at t <= 10, b: 0
  EXPECT_DOUBLE_EQ(series[0].catastrophic_mean(), 0);
  EXPECT_DOUBLE_EQ(series[1].catastrophic_mean(), 0.5);
  ASSERT_EQ(series[1].conjunctions_mean_size(), 1);
  EXPECT_DOUBLE_EQ(series[1].conjunctions_mean(0), 1.5);
  EXPECT_TRUE(server::aggregate_series({}).empty());
}

TEST(EnsembleState, FromTheMembers) {
  using S = std::map<v1::RunState, std::uint64_t>;
  EXPECT_EQ(server::ensemble_state(S{{v1::RUN_STATE_QUEUED, 3}}), v1::RUN_STATE_QUEUED);
  EXPECT_EQ(server::ensemble_state(S{{v1::RUN_STATE_QUEUED, 2}, {v1::RUN_STATE_SUCCEEDED, 1}}),
            v1::RUN_STATE_RUNNING);
  EXPECT_EQ(server::ensemble_state(S{{v1::RUN_STATE_SUCCEEDED, 2}, {v1::RUN_STATE_CANCELLED, 1}}),
            v1::RUN_STATE_CANCELLED);
  EXPECT_EQ(server::ensemble_state(S{{v1::RUN_STATE_FAILED, 1}, {v1::RUN_STATE_CANCELLED, 1}}),
            v1::RUN_STATE_FAILED);
  EXPECT_EQ(server::ensemble_state(S{{v1::RUN_STATE_SUCCEEDED, 3}}), v1::RUN_STATE_SUCCEEDED);
}

}  // namespace
}  // namespace kessler
