// Hostile requests, one row each, against the real kesslerd on loopback: every finding of the request
// kind is refused with INVALID_ARGUMENT naming its field (before any large allocation), and the daemon
// keeps serving. Large submissions: GetRun leaves inline data out unless asked; errors quote at most
// a short prefix of bad input.
#include <grpcpp/grpcpp.h>
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "kessler/v1/service.grpc.pb.h"
#include "tests/service/service_harness.hpp"

namespace kessler {
namespace {

using test::Daemon;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

struct LimitFinding {
  const char* name;
  const char* field;  // expected at the start of the message and in kessler-field-path
  std::function<grpc::Status(v1::KesslerService::Stub&, grpc::ClientContext&, std::int64_t run_id)> call;
};

template <typename Request>
Request for_run(std::int64_t run_id) {
  Request r;
  r.set_run_id(run_id);
  return r;
}

grpc::Status stats(v1::KesslerService::Stub& s, grpc::ClientContext& c, const v1::GetRunStatsRequest& r) {
  v1::RunStats out;
  return s.GetRunStats(&c, r, &out);
}
grpc::Status conjunctions(v1::KesslerService::Stub& s, grpc::ClientContext& c,
                          const v1::ListConjunctionsRequest& r) {
  v1::ListConjunctionsResponse out;
  return s.ListConjunctions(&c, r, &out);
}
grpc::Status list_runs(v1::KesslerService::Stub& s, grpc::ClientContext& c, const v1::ListRunsRequest& r) {
  v1::ListRunsResponse out;
  return s.ListRuns(&c, r, &out);
}

std::vector<LimitFinding> limit_findings() {
  std::vector<LimitFinding> rows;
  // GetRunStats: an 8 KB request asking for a billion cells, and numbers that are not numbers.
  rows.push_back({"stats: tiny time bin", "time_bin_s", [](auto& s, auto& c, std::int64_t id) {
                    auto r = for_run<v1::GetRunStatsRequest>(id);
                    r.set_time_bin_s(1e-6);
                    for (int i = 0; i < 64; ++i) r.add_kappas(1 + i);
                    return stats(s, c, r);
                  }});
  rows.push_back({"stats: 1000 kappas", "kappas", [](auto& s, auto& c, std::int64_t id) {
                    auto r = for_run<v1::GetRunStatsRequest>(id);
                    for (int i = 0; i < 1000; ++i) r.add_kappas(1 + i);
                    return stats(s, c, r);
                  }});
  for (double bad : {kNaN, -1.0, 0.0, kInf})
    rows.push_back(
        {"stats: kappa not positive and finite", "kappas[1]", [bad](auto& s, auto& c, std::int64_t id) {
           auto r = for_run<v1::GetRunStatsRequest>(id);
           r.add_kappas(1);
           r.add_kappas(bad);
           return stats(s, c, r);
         }});
  for (double bad : {kNaN, -5.0, kInf})
    rows.push_back({"stats: bad time bin", "time_bin_s", [bad](auto& s, auto& c, std::int64_t id) {
                      auto r = for_run<v1::GetRunStatsRequest>(id);
                      r.set_time_bin_s(bad);
                      return stats(s, c, r);
                    }});
  // Filters: NaN matched nothing, silently.
  rows.push_back({"conjunctions: NaN kappa_min", "kappa_min", [](auto& s, auto& c, std::int64_t id) {
                    auto r = for_run<v1::ListConjunctionsRequest>(id);
                    r.set_kappa_min(kNaN);
                    return conjunctions(s, c, r);
                  }});
  rows.push_back({"conjunctions: infinite time_max_s", "time_max_s", [](auto& s, auto& c, std::int64_t id) {
                    auto r = for_run<v1::ListConjunctionsRequest>(id);
                    r.set_time_max_s(kInf);
                    return conjunctions(s, c, r);
                  }});
  // Page tokens and sizes.
  for (const char* token : {"-1", "1.5", "3abc", " 7", "99999999999999999999"}) {
    rows.push_back({"runs: bad page token", "page_token", [token](auto& s, auto& c, std::int64_t) {
                      v1::ListRunsRequest r;
                      r.set_page_token(token);
                      return list_runs(s, c, r);
                    }});
    rows.push_back({"conjunctions: bad page token", "page_token", [token](auto& s, auto& c, std::int64_t id) {
                      auto r = for_run<v1::ListConjunctionsRequest>(id);
                      r.set_page_token(token);
                      return conjunctions(s, c, r);
                    }});
    rows.push_back({"fragments: bad page token", "page_token", [token](auto& s, auto& c, std::int64_t id) {
                      auto r = for_run<v1::ListFragmentsRequest>(id);
                      r.set_page_token(token);
                      v1::ListFragmentsResponse out;
                      return s.ListFragments(&c, r, &out);
                    }});
    rows.push_back({"ensembles: bad page token", "page_token", [token](auto& s, auto& c, std::int64_t) {
                      v1::ListEnsemblesRequest r;
                      r.set_page_token(token);
                      v1::ListEnsemblesResponse out;
                      return s.ListEnsembles(&c, r, &out);
                    }});
  }
  rows.push_back({"runs: negative page size", "page_size", [](auto& s, auto& c, std::int64_t) {
                    v1::ListRunsRequest r;
                    r.set_page_size(-1);
                    return list_runs(s, c, r);
                  }});
  rows.push_back({"runs: unknown state number", "states[0]", [](auto& s, auto& c, std::int64_t) {
                    v1::ListRunsRequest r;
                    r.add_states(static_cast<v1::RunState>(42));
                    return list_runs(s, c, r);
                  }});
  rows.push_back({"watch: after_seq >= 2^63", "after_seq", [](auto& s, auto& c, std::int64_t id) {
                    auto r = for_run<v1::WatchRunRequest>(id);
                    r.set_after_seq(std::uint64_t{1} << 63);
                    auto reader = s.WatchRun(&c, r);
                    v1::RunEvent event;
                    while (reader->Read(&event)) {
                    }
                    return reader->Finish();
                  }});
  rows.push_back({"ensemble: 65 kappas", "kappas", [](auto& s, auto& c, std::int64_t) {
                    v1::GetEnsembleRequest r;
                    r.set_ensemble_id(1);
                    for (int i = 0; i < 65; ++i) r.add_kappas(1 + i);
                    v1::EnsembleReport out;
                    return s.GetEnsemble(&c, r, &out);
                  }});
  // Submissions: numbers in the scenario message, request ids.
  rows.push_back({"submit: NaN dt_s", "dt_s", [](auto& s, auto& c, std::int64_t) {
                    v1::SubmitRunRequest r;
                    r.mutable_scenario()->set_name("nan");
                    r.mutable_scenario()->set_dt_s(kNaN);
                    v1::Run out;
                    return s.SubmitRun(&c, r, &out);
                  }});
  rows.push_back({"submit: infinite screening distance", "conjunctions.screening_distance_km",
                  [](auto& s, auto& c, std::int64_t) {
                    v1::SubmitRunRequest r;
                    r.mutable_scenario()->mutable_conjunctions()->set_screening_distance_km(kInf);
                    v1::Run out;
                    return s.SubmitRun(&c, r, &out);
                  }});
  rows.push_back({"submit: request id of 200 characters", "request_id", [](auto& s, auto& c, std::int64_t) {
                    v1::SubmitRunRequest r;
                    r.set_scenario_text(test::read_text(test::kTinyScenario));
                    r.set_request_id(std::string(200, 'x'));
                    v1::Run out;
                    return s.SubmitRun(&c, r, &out);
                  }});
  rows.push_back({"submit: infinite altitude in the text", "population.synthetic.max_altitude_km",
                  [](auto& s, auto& c, std::int64_t) {
                    v1::SubmitRunRequest r;
                    r.set_scenario_text(
                        "name: inf\npopulation:\n  synthetic:\n    objects: 10\n    max_altitude_km: .inf\n");
                    v1::Run out;
                    return s.SubmitRun(&c, r, &out);
                  }});
  return rows;
}

class RequestFindings : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir = new TempDir;
    daemon = new Daemon(dir->path() + "/k.db");
    daemon->start();
    stub = v1::KesslerService::NewStub(
               grpc::CreateChannel(daemon->address(), grpc::InsecureChannelCredentials()))
               .release();
    v1::SubmitRunRequest request;
    request.set_scenario_text(test::read_text(test::kTinyScenario));
    grpc::ClientContext context;
    v1::Run run;
    if (!stub->SubmitRun(&context, request, &run).ok()) throw std::runtime_error("submit failed");
    run_id = run.id();
  }
  static void TearDownTestSuite() {
    delete stub;
    delete daemon;
    delete dir;
  }
  static inline TempDir* dir = nullptr;
  static inline Daemon* daemon = nullptr;
  static inline v1::KesslerService::Stub* stub = nullptr;
  static inline std::int64_t run_id = 0;
};

TEST_F(RequestFindings, EachIsRefusedNamingItsField) {
  for (const LimitFinding& f : limit_findings()) {
    SCOPED_TRACE(f.name);
    grpc::ClientContext context;
    context.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(30));
    grpc::Status status = f.call(*stub, context, run_id);
    EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT) << status.error_message();
    EXPECT_EQ(status.error_message().rfind(std::string(f.field) + ":", 0), 0u) << status.error_message();
    auto path = context.GetServerTrailingMetadata().find("kessler-field-path");
    ASSERT_NE(path, context.GetServerTrailingMetadata().end());
    EXPECT_EQ(std::string(path->second.data(), path->second.size()), f.field);
  }
  EXPECT_TRUE(daemon->alive());
  grpc::ClientContext context;
  v1::ListRunsResponse runs;
  EXPECT_TRUE(stub->ListRuns(&context, v1::ListRunsRequest(), &runs).ok());
}

TEST_F(RequestFindings, ErrorsQuoteAShortPrefixOfBadInput) {
  // A 1 MB scenario text that does not parse, and a 1 MB name in a page token.
  v1::SubmitRunRequest request;
  request.set_scenario_text("name: " + std::string(1 << 20, 'x') + "\n: : :\n");
  grpc::ClientContext context;
  v1::Run run;
  auto status = stub->SubmitRun(&context, request, &run);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT) << status.error_message().substr(0, 200);
  EXPECT_LE(status.error_message().size(), 1100u);
  v1::ListRunsRequest list;
  list.set_page_token(std::string(1 << 20, '7') + "x");
  grpc::ClientContext list_context;
  v1::ListRunsResponse runs;
  status = stub->ListRuns(&list_context, list, &runs);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_LE(status.error_message().size(), 200u) << status.error_message().substr(0, 300);
}

TEST_F(RequestFindings, GetRunLeavesInlineDataOutUnlessAsked) {
  const std::string scenario = test::read_text(test::source_path("tests/scenario/data/catalog-small.yaml"));
  v1::SubmitRunRequest request;
  request.set_scenario_text(scenario);
  request.set_request_id("inline-1");
  grpc::ClientContext context;
  v1::Run run;
  ASSERT_TRUE(stub->SubmitRun(&context, request, &run).ok());
  v1::GetRunRequest get;
  get.set_run_id(run.id());
  grpc::ClientContext plain_context;
  v1::Run plain;
  ASSERT_TRUE(stub->GetRun(&plain_context, get, &plain).ok());
  EXPECT_TRUE(plain.scenario().population().has_catalog());
  EXPECT_TRUE(plain.scenario().population().catalog().text().empty());
  EXPECT_GT(plain.inline_data_omitted_bytes(), 20000u);
  get.set_include_inline_data(true);
  grpc::ClientContext full_context;
  v1::Run full;
  ASSERT_TRUE(stub->GetRun(&full_context, get, &full).ok());
  EXPECT_EQ(full.scenario().population().catalog().text().size(), plain.inline_data_omitted_bytes());
  EXPECT_NE(full.scenario().population().catalog().text().find("VANGUARD 1"), std::string::npos);
}

}  // namespace
}  // namespace kessler
