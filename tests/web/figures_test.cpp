// The numbers behind each figure against the store (the conjunction listing's counts, the run's
// summary) and against the scenario's geometry: pairs aimed to pass at kappa 0.75 (a collision), 1.5,
// 3.75 and 7.5, one object falling through the burn-up altitude.
#include <gtest/gtest.h>

#include <chrono>
#include <map>
#include <thread>

#include "server/figures/figures.hpp"
#include "tests/web/web_harness.hpp"

namespace kessler {
namespace {

using nlohmann::json;
using test::shared_run;

const json& spec_of(const std::vector<server::figures::Figure>& figures, const std::string& id) {
  for (const auto& f : figures)
    if (f.id == id) return f.spec;
  throw std::runtime_error("no figure " + id);
}

std::uint64_t store_count_at(double kappa) {
  v1::ListConjunctionsRequest request;
  request.set_run_id(shared_run().run_id);
  request.set_kappa_max(kappa);
  return shared_run().manager->conjunctions(request).total();
}

// The figures from the run's stats and events, then those from its snapshots and conjunctions (no
// Gabbard diagram: the run has no breakup).
TEST(Figures, TheRunGetsEveryFigureThatApplies) {
  auto figures = server::figures::figures_for_run(*shared_run().manager, shared_run().run_id);
  std::vector<std::string> ids;
  for (const auto& f : figures) {
    ids.push_back(f.id);
    EXPECT_FALSE(f.partial);
    EXPECT_EQ(f.spec["$schema"], "https://vega.github.io/schema/vega-lite/v5.json");
  }
  EXPECT_EQ(ids, (std::vector<std::string>{"conjunctions-over-time", "conjunctions-vs-kappa",
                                           "runtime-breakdown", "objects-by-type", "population-distributions",
                                           "conjunction-sizes", "conjunction-orbits", "spatial-density"}));
}

TEST(Figures, EachKappaCurveEndsAtTheStoresCountAtThatKappa) {
  auto figures = server::figures::figures_for_run(*shared_run().manager, shared_run().run_id);
  std::map<std::string, double> last;
  for (const json& row : spec_of(figures, "conjunctions-over-time")["data"]["values"])
    last[row["kappa"].get<std::string>()] = row["n"].get<double>();
  ASSERT_EQ(last.size(), 4u);
  // The geometry: one pass at kappa 0.75, 1.5, 3.75 and 7.5 each (the 500 m pair is no conjunction).
  const std::map<double, double> aimed = {{1, 1}, {2, 2}, {5, 3}, {10, 4}};
  for (auto [kappa, expected] : aimed) {
    char label[32];
    std::snprintf(label, sizeof label, "kappa <= %g", kappa);
    EXPECT_EQ(last.at(label), static_cast<double>(store_count_at(kappa))) << label;
    EXPECT_EQ(last.at(label), expected) << label;
  }
}

TEST(Figures, TheTotalAgainstKappaIsTheStoresCountAtEachKappa) {
  auto figures = server::figures::figures_for_run(*shared_run().manager, shared_run().run_id);
  const json& rows = spec_of(figures, "conjunctions-vs-kappa")["data"]["values"];
  ASSERT_EQ(rows.size(), server::figures::kSweepKappas.size());
  for (const json& row : rows)
    EXPECT_EQ(row["n"].get<std::uint64_t>(), store_count_at(row["kappa"].get<double>())) << row.dump();
}

TEST(Figures, TheRuntimeBarsAreTheSummarysPhaseTimers) {
  auto figures = server::figures::figures_for_run(*shared_run().manager, shared_run().run_id);
  const v1::PhaseTimers& t = shared_run().run.summary().timers();
  const std::map<std::string, double> expected = {
      {"integrator", t.integrator_s()}, {"burn-up", t.burn_up_s()}, {"grid", t.grid_s()},
      {"detection", t.detection_s()},   {"output", t.output_s()},   {"checkpoint", t.checkpoint_s()}};
  const json& rows = spec_of(figures, "runtime-breakdown")["data"]["values"];
  ASSERT_EQ(rows.size(), 6u);
  for (const json& row : rows)
    EXPECT_EQ(row["s"].get<double>(), expected.at(row["phase"].get<std::string>()));
}

TEST(Figures, ObjectsOnOrbitStartAndEndAtTheRunsCountsWithTheReentryMarked) {
  auto figures = server::figures::figures_for_run(*shared_run().manager, shared_run().run_id);
  const json& layers = spec_of(figures, "objects-by-type")["layer"];
  ASSERT_EQ(layers.size(), 2u);
  std::vector<double> all;
  for (const json& row : layers[0]["data"]["values"])
    if (row["type"] == "all objects") all.push_back(row["n"].get<double>());
  ASSERT_FALSE(all.empty());
  EXPECT_EQ(all.back(), static_cast<double>(shared_run().run.summary().objects_final()));
  EXPECT_EQ(all.back(), 10.0);  // 11 at the start, one burnt up
  const json& marks = layers[1]["data"]["values"];
  ASSERT_EQ(marks.size(), 1u);
  EXPECT_EQ(marks[0]["event"], "re-entries");
  EXPECT_EQ(marks[0]["count"], 1);
}

TEST(Figures, RefusalsNameTheField) {
  auto& m = *shared_run().manager;
  try {
    server::figures::figures_for_run(m, 999);
    FAIL() << "no error for an unknown run";
  } catch (const server::ServiceError& e) {
    EXPECT_EQ(e.code, server::ServiceError::Code::kNotFound);
  }
  v1::GetFiguresRequest request;
  request.set_run_id(shared_run().run_id);
  for (int i = 0; i < 17; ++i) request.add_compare_run_ids(shared_run().run_id);
  try {
    m.figures(request);
    FAIL() << "no error for 17 compared runs";
  } catch (const server::ServiceError& e) {
    EXPECT_EQ(e.field_path, "compare_run_ids");
  }
}

TEST(Figures, ComparedRunsAreDrawnSideBySide) {
  auto& m = *shared_run().manager;
  v1::GetFiguresRequest request;
  request.set_run_id(shared_run().run_id);
  request.add_compare_run_ids(shared_run().run_id);  // the same run twice counts once
  auto once = m.figures(request);
  v1::SubmitRunRequest submit;
  submit.set_scenario_text(test::crossings_scenario());
  const std::int64_t second = m.submit(submit).id();
  test::wait_for(m, second, [](const v1::Run& r) { return server::is_terminal(r.state()); });
  request.clear_compare_run_ids();
  request.add_compare_run_ids(second);
  auto both = m.figures(request);
  ASSERT_EQ(both.figures_size(), 8);  // the run's own snapshot figures after the four compared
  json spec = json::parse(both.figures(2).vega_lite_json());  // runtime, one bar per run and phase
  EXPECT_EQ(spec["data"]["values"].size(), 12u);
  EXPECT_TRUE(spec["encoding"].contains("xOffset"));
  EXPECT_EQ(json::parse(once.figures(2).vega_lite_json())["data"]["values"].size(), 6u);
  m.remove(second);
}

}  // namespace
}  // namespace kessler

namespace kessler {
namespace {

// An ensemble of the crossings run (three seeds; the orbits do not depend on the seed): its figures
// are the members' means, with the 5-95 % band of objects on orbit and of each phase's time.
TEST(Figures, AnEnsembleGetsMeansWithBands) {
  auto& m = *test::shared_run().manager;
  v1::SubmitEnsembleRequest submit;
  submit.set_scenario_text(test::crossings_scenario());
  submit.set_members(3);
  const std::int64_t id = m.submit_ensemble(submit).id();
  v1::GetEnsembleRequest get;
  get.set_ensemble_id(id);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
  while (!server::is_terminal(m.get_ensemble(get).state()) && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  m.store().flush();  // the members' last events committed
  auto figures = server::figures::figures_for_ensemble(m, id);
  ASSERT_EQ(figures.size(), 4u);
  for (const auto& f : figures) EXPECT_FALSE(f.partial) << f.id;
  // The kappa curves' means end at the single run's counts (every member has the same passes).
  std::map<std::string, double> last;
  for (const json& row : spec_of(figures, "conjunctions-over-time")["data"]["values"])
    last[row["kappa"].get<std::string>()] = row["n"].get<double>();
  EXPECT_EQ(last.at("kappa <= 1"), 1.0);
  EXPECT_EQ(last.at("kappa <= 10"), 4.0);
  // The members have the same passes: their 5-95 % band is the mean itself, drawn under the lines.
  const json& over_time = spec_of(figures, "conjunctions-over-time");
  EXPECT_EQ(over_time["layer"][0]["mark"]["type"], "area");
  EXPECT_EQ(over_time["layer"][1]["mark"]["type"], "line");
  for (const json& row : over_time["data"]["values"]) {
    EXPECT_EQ(row["p05"], row["n"]);
    EXPECT_EQ(row["p95"], row["n"]);
  }
  for (const json& row : spec_of(figures, "conjunctions-vs-kappa")["data"]["values"])
    EXPECT_EQ(row["p95"], row["n"]) << row.dump();
  const json& objects = spec_of(figures, "objects-by-type")["layer"];
  EXPECT_EQ(objects[0]["mark"]["type"], "area");  // the band
  EXPECT_EQ(objects[0]["data"]["values"].back()["p05"], 10.0);
  EXPECT_EQ(objects[0]["data"]["values"].back()["p95"], 10.0);
  const json& runtime = spec_of(figures, "runtime-breakdown")["layer"];
  EXPECT_EQ(runtime[1]["mark"], "rule");
  EXPECT_FALSE(runtime[0].contains("data"));  // the bars read the spec's data
  for (const json& row : spec_of(figures, "runtime-breakdown")["data"]["values"]) {
    EXPECT_LE(row["p05"].get<double>(), row["s"].get<double>());
    EXPECT_GE(row["p95"].get<double>(), row["s"].get<double>());
  }
  v1::GetFiguresRequest bad;
  bad.set_ensemble_id(id);
  bad.add_compare_run_ids(1);
  EXPECT_THROW(m.figures(bad), server::ServiceError);
}

}  // namespace
}  // namespace kessler
