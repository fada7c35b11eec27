// Population snapshots and the figures end to end: a run with snapshots and an explosion on a daemon in
// this process, its gRPC API on loopback and the real kessler binary. ListSnapshots and GetSnapshot
// (steps, times, filters, pages, bad requests), the figures' numbers against the store's (histogram
// counts sum to the snapshot's objects, spatial density integrated over its shells gives the object
// count, conjunction pairs to the listed conjunctions, Gabbard points to the fragments on orbit), and
// `kessler snapshot`.
#include <grpcpp/grpcpp.h>
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <set>
#include <sstream>

#include "core/scenario/run_builder.hpp"
#include "kessler/v1/service.grpc.pb.h"
#include "server/api_server.hpp"
#include "server/figures/snapshot_figures.hpp"
#include "server/run_manager.hpp"
#include "tests/service/in_process_service.hpp"
#include "tests/service/service_harness.hpp"

namespace kessler {
namespace {

using test::cli;

// 43 steps of 10 s; a snapshot every 0.001 days (86.4 s: 9 steps) and at the last step.
const char* const kSnapshotScenario = R"yaml(
name: snapshot-e2e
duration_days: 0.005
dt_s: 10
population:
  dataset: leo-19647
  max_objects: 300
conjunctions:
  screening_distance_km: 30
snapshots:
  every_days: 0.001
seed: 5
)yaml";

constexpr std::int64_t kExplosionStep = 6;

class SnapshotEndToEnd : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { shared_ = new Shared(test::parsed_scenario(kSnapshotScenario)); }
  static void TearDownTestSuite() {
    delete shared_;
    shared_ = nullptr;
  }

  struct Shared : test::InProcessService {
    explicit Shared(const v1::Scenario& parsed)
        : InProcessService(test::explode_at(test::first_object(parsed), kExplosionStep)), scenario(parsed) {
      run = submit(scenario);
      watch(run.id(), 0, true, &final_state);
      run = manager->get(run.id());
    }
    v1::Scenario scenario;
    v1::Run run;
    v1::RunState final_state = v1::RUN_STATE_UNSPECIFIED;
  };

  static grpc::Status get(v1::GetSnapshotRequest request, v1::GetSnapshotResponse& out) {
    request.set_run_id(shared_->run.id());
    grpc::ClientContext context;
    return shared_->stub->GetSnapshot(&context, request, &out);
  }
  static std::string run_id() { return std::to_string(shared_->run.id()); }
  static Shared* shared_;
};

SnapshotEndToEnd::Shared* SnapshotEndToEnd::shared_ = nullptr;

TEST_F(SnapshotEndToEnd, ListsTheStartEveryIntervalAndTheLastStep) {
  ASSERT_EQ(shared_->final_state, v1::RUN_STATE_SUCCEEDED);
  v1::ListSnapshotsRequest request;
  request.set_run_id(shared_->run.id());
  request.set_page_size(4);
  std::vector<std::int64_t> steps;
  std::vector<v1::SnapshotInfo> rows;
  for (;;) {
    grpc::ClientContext context;
    v1::ListSnapshotsResponse response;
    ASSERT_TRUE(shared_->stub->ListSnapshots(&context, request, &response).ok());
    EXPECT_EQ(response.total(), 6u);
    rows.insert(rows.end(), response.snapshots().begin(), response.snapshots().end());
    if (response.next_page_token().empty()) break;
    request.set_page_token(response.next_page_token());
  }
  for (const auto& r : rows) steps.push_back(r.step());
  EXPECT_EQ(steps, (std::vector<std::int64_t>{0, 9, 18, 27, 36, 43}));
  EXPECT_EQ(rows[1].epoch(), "2022-03-01T00:01:30.000Z");
  EXPECT_EQ(rows.front().objects(), shared_->run.summary().objects_initial());
  EXPECT_EQ(rows.back().objects(), shared_->run.summary().objects_final());
  EXPECT_GT(rows.back().objects(), rows.front().objects());  // the explosion's fragments
}

TEST_F(SnapshotEndToEnd, GetsTheLastSnapshotAtOrBeforeAStepTimeOrEpoch) {
  v1::GetSnapshotResponse r;
  const grpc::Status status = get({}, r);
  ASSERT_TRUE(status.ok()) << status.error_code() << " " << status.error_message();
  EXPECT_EQ(r.snapshot().step(), 43);
  EXPECT_EQ(r.total(), shared_->run.summary().objects_final());
  v1::GetSnapshotRequest at;
  at.set_step(20);
  ASSERT_TRUE(get(at, r).ok());
  EXPECT_EQ(r.snapshot().step(), 18);
  at.set_sim_time_s(100.0);
  ASSERT_TRUE(get(at, r).ok());
  EXPECT_EQ(r.snapshot().step(), 9);
  at.set_epoch("2022-03-01T00:06:00Z");
  ASSERT_TRUE(get(at, r).ok());
  EXPECT_EQ(r.snapshot().step(), 36);
  // Elements that describe the orbits: LEO altitudes, perigee below apogee.
  for (const auto& o : r.objects()) {
    EXPECT_GT(o.perigee_altitude_km(), 100.0) << o.id();
    EXPECT_LE(o.perigee_altitude_km(), o.apogee_altitude_km() + 1e-9);
    EXPECT_NEAR(o.semi_major_axis_km() - 6378.137, 0.5 * (o.perigee_altitude_km() + o.apogee_altitude_km()),
                1e-6);
  }
}

TEST_F(SnapshotEndToEnd, FiltersAndPagesTheObjects) {
  v1::GetSnapshotResponse all;
  v1::GetSnapshotRequest request;
  request.set_page_size(100000);
  ASSERT_TRUE(get(request, all).ok());
  std::uint64_t fragments = 0, band = 0, small = 0;
  for (const auto& o : all.objects()) {
    fragments += o.kind() == v1::OBJECT_KIND_FRAGMENT;
    band += o.apogee_altitude_km() >= 700.0 && o.perigee_altitude_km() <= 800.0;
    small += o.radius_m() <= 0.5;
  }
  ASSERT_GT(fragments, 0u);
  v1::GetSnapshotResponse r;
  request.add_kinds(v1::OBJECT_KIND_FRAGMENT);
  ASSERT_TRUE(get(request, r).ok());
  EXPECT_EQ(r.total(), fragments);
  for (const auto& o : r.objects()) EXPECT_GE(o.id(), kFirstFragmentId);
  request.clear_kinds();
  request.set_min_altitude_km(700.0);
  request.set_max_altitude_km(800.0);
  ASSERT_TRUE(get(request, r).ok());
  EXPECT_EQ(r.total(), band);
  request.clear_min_altitude_km();
  request.clear_max_altitude_km();
  request.set_max_radius_m(0.5);
  ASSERT_TRUE(get(request, r).ok());
  EXPECT_EQ(r.total(), small);
  // Pages of 100 give every object once, in order.
  v1::GetSnapshotRequest paged;
  paged.set_page_size(100);
  std::vector<std::uint64_t> ids;
  for (;;) {
    ASSERT_TRUE(get(paged, r).ok());
    for (const auto& o : r.objects()) ids.push_back(o.id());
    if (r.next_page_token().empty()) break;
    paged.set_page_token(r.next_page_token());
  }
  ASSERT_EQ(ids.size(), static_cast<std::size_t>(all.objects_size()));
  for (std::size_t i = 0; i < ids.size(); ++i) EXPECT_EQ(ids[i], all.objects(static_cast<int>(i)).id());
}

TEST_F(SnapshotEndToEnd, RefusesBadRequestsNamingTheField) {
  v1::GetSnapshotResponse r;
  v1::GetSnapshotRequest bad;
  bad.add_kinds(static_cast<v1::ObjectKind>(42));
  grpc::Status s = get(bad, r);
  EXPECT_EQ(s.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_EQ(s.error_message().rfind("kinds: ", 0), 0u) << s.error_message();
  bad.Clear();
  bad.set_epoch("yesterday");
  EXPECT_EQ(get(bad, r).error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  bad.Clear();
  bad.set_page_token("nope");
  EXPECT_EQ(get(bad, r).error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  bad.Clear();
  bad.set_step(-5);
  EXPECT_EQ(get(bad, r).error_code(), grpc::StatusCode::NOT_FOUND);
  grpc::ClientContext context;
  v1::GetSnapshotRequest unknown;
  unknown.set_run_id(999);
  EXPECT_EQ(shared_->stub->GetSnapshot(&context, unknown, &r).error_code(), grpc::StatusCode::NOT_FOUND);
}

double sum_of(const nlohmann::json& values, const char* key) {
  double total = 0.0;
  for (const auto& v : values) total += v.at(key).get<double>();
  return total;
}

TEST_F(SnapshotEndToEnd, TheFiguresNumbersAgreeWithTheStore) {
  server::RunManager& m = *shared_->manager;
  const std::int64_t id = shared_->run.id();
  const nlohmann::json figures = server::run_figures(m, id);
  const PopulationSnapshot first = *m.population_snapshot(id, 0);
  const PopulationSnapshot last = *m.population_snapshot(id, std::nullopt);

  // 1: each panel's counts sum to the first snapshot's objects.
  const nlohmann::json& distributions = figures.at("population_distributions");
  ASSERT_EQ(distributions.at("hconcat").size(), 3u);
  for (const auto& panel : distributions.at("hconcat"))
    EXPECT_EQ(sum_of(panel.at("data").at("values"), "count"), static_cast<double>(first.size()));
  EXPECT_EQ(distributions.at("$schema"), "https://vega.github.io/schema/vega-lite/v5.json");

  // 7: density times shell volume, summed, gives the object count at the start and at the end.
  for (const PopulationSnapshot* s : {&first, &last}) {
    const DensityProfile p = spatial_density(*s, 100.0, 2500.0);
    double objects = 0.0;
    for (std::size_t k = 0; k < p.objects_per_km3.size(); ++k) {
      const double r0 = 6378.137 + p.first_altitude_km + p.shell_km * static_cast<double>(k);
      const double r1 = r0 + p.shell_km;
      objects += p.objects_per_km3[k] * 4.0 / 3.0 * std::numbers::pi * (r1 * r1 * r1 - r0 * r0 * r0);
    }
    EXPECT_NEAR(objects, static_cast<double>(s->size()), 1e-6 * static_cast<double>(s->size()));
    EXPECT_EQ(p.objects + p.unbound, s->size());
  }
  ASSERT_FALSE(figures.at("spatial_density").is_null());

  // 3 and 4: every listed conjunction between objects of the first snapshot is one cell count, and
  // two objects in the orbit histograms.
  v1::ListConjunctionsRequest list;
  list.set_run_id(id);
  list.set_page_size(100000);
  const v1::ListConjunctionsResponse conjunctions = m.conjunctions(list);
  ASSERT_GT(conjunctions.total(), 0u);
  std::set<ObjectId> at_start(first.id.begin(), first.id.end());
  std::uint64_t between_start_objects = 0;
  for (const auto& c : conjunctions.conjunctions())
    between_start_objects += at_start.count(c.id1()) != 0 && at_start.count(c.id2()) != 0;
  const nlohmann::json& sizes = figures.at("conjunction_sizes");
  ASSERT_FALSE(sizes.is_null());
  EXPECT_EQ(sum_of(sizes.at("hconcat")[0].at("data").at("values"), "conjunctions"),
            static_cast<double>(between_start_objects));
  double in_conjunctions = 0.0;
  for (const auto& v : sizes.at("hconcat")[1].at("data").at("values"))
    if (v.at("group") == "objects in conjunctions") in_conjunctions += v.at("count").get<double>();
  EXPECT_EQ(in_conjunctions, 2.0 * static_cast<double>(between_start_objects));
  double altitude_counts = 0.0;
  for (const auto& v : figures.at("conjunction_orbits").at("hconcat")[0].at("data").at("values"))
    if (v.at("group") == "objects in conjunctions" && v.at("quantity") == "altitude")
      altitude_counts += v.at("count").get<double>();
  EXPECT_EQ(altitude_counts, 2.0 * static_cast<double>(conjunctions.total()));

  // 8: two points (apogee, perigee) per fragment on orbit in each chosen snapshot.
  const nlohmann::json& gabbard = figures.at("gabbard");
  ASSERT_FALSE(gabbard.is_null());
  std::map<std::string, std::uint64_t> points;
  for (const auto& v : gabbard.at("data").at("values")) ++points[v.at("when").get<std::string>()];
  std::uint64_t fragments_last = 0;
  for (ObjectId o : last.id) fragments_last += o >= kFirstFragmentId;
  ASSERT_GT(fragments_last, 0u);
  EXPECT_EQ(points.size(), 4u);                         // the snapshots at steps 18, 27, 36, 43
  EXPECT_EQ(points["t = 0.12 h"], 2 * fragments_last);  // 430 s
}

TEST_F(SnapshotEndToEnd, FiguresOfARunWithoutSnapshotsAreNull) {
  v1::SubmitRunRequest submit;
  *submit.mutable_scenario() = shared_->scenario;
  submit.mutable_scenario()->mutable_snapshots()->set_every_days(0);
  const v1::Run run = shared_->manager->submit(submit);
  const nlohmann::json figures = server::run_figures(*shared_->manager, run.id());
  for (const char* name : {"population_distributions", "spatial_density", "gabbard"})
    EXPECT_TRUE(figures.at(name).is_null()) << name;
  EXPECT_THROW(server::run_figures(*shared_->manager, 12345), server::ServiceError);
}

TEST_F(SnapshotEndToEnd, TheCliPrintsCsvAndJsonAndRefusesAnUnknownKind) {
  const std::string server = " --server " + shared_->address;
  auto csv = cli(shared_->dir, "snapshot " + run_id() + " --output csv" + server);
  ASSERT_EQ(csv.exit_code, 0) << csv.err;
  std::istringstream lines(csv.out);
  std::string header, line;
  std::getline(lines, header);
  EXPECT_EQ(header.rfind("id,kind,active,radius_m,mass_kg,semi_major_axis_km", 0), 0u);
  std::uint64_t rows = 0;
  while (std::getline(lines, line)) rows += !line.empty();
  EXPECT_EQ(rows, shared_->run.summary().objects_final());
  auto json = cli(shared_->dir, "snapshot " + run_id() +
                                    " --at 2022-03-01T00:01:40Z --kind fragment --output json" + server);
  ASSERT_EQ(json.exit_code, 0) << json.err;
  EXPECT_NE(json.out.find("\"step\":9,"), std::string::npos) << json.out.substr(0, 200);
  EXPECT_NE(json.out.find("\"kind\": \"fragment\""), std::string::npos) << json.out.substr(0, 300);
  EXPECT_EQ(json.out.find("\"kind\": \"payload\""), std::string::npos);
  auto list = cli(shared_->dir, "snapshot " + run_id() + " --list" + server);
  ASSERT_EQ(list.exit_code, 0) << list.err;
  EXPECT_NE(list.out.find("\n43,430,2022-03-01T00:07:10.000Z,"), std::string::npos) << list.out;
  auto bad = cli(shared_->dir, "snapshot " + run_id() + " --kind comet" + server);
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("--kind: unknown kind 'comet'"), std::string::npos) << bad.err;
}

}  // namespace
}  // namespace kessler
