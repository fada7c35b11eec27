// The dashboard's HTTP answers, on loopback over the shared run: bad parameters are 400 with a JSON
// error naming the parameter, unknown paths and runs 404, listings paged and bounded, sorted, CSV.
#include <gtest/gtest.h>

#include "server/http/http_server.hpp"
#include "tests/web/web_harness.hpp"
// httplib after the server's headers (resolv.h's _res macro breaks Eigen's headers).
#include <httplib.h>
#include <nlohmann/json.hpp>

#include <set>

namespace kessler {
namespace {

using nlohmann::json;

class Dashboard : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    server_ = new server::HttpServer(*test::shared_run().manager, "127.0.0.1:0");
  }
  static void TearDownTestSuite() {
    delete server_;
    server_ = nullptr;
  }
  httplib::Result get(const std::string& path) {
    httplib::Client client("127.0.0.1", server_->port());
    return client.Get(path.c_str());
  }
  std::string run_path(const std::string& rest) {
    return "/api/runs/" + std::to_string(test::shared_run().run_id) + rest;
  }
  static server::HttpServer* server_;
};
server::HttpServer* Dashboard::server_ = nullptr;

TEST_F(Dashboard, BadParametersAre400WithTheParameterNamed) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {run_path("/conjunctions?page_size=0"), "page_size"},
      {run_path("/conjunctions?page_size=1001"), "page_size"},
      {run_path("/conjunctions?format=csv&page_size=100001"), "page_size"},
      {run_path("/conjunctions?kappa_max=abc"), "kappa_max"},
      {run_path("/conjunctions?kappa_min=5&kappa_max=1"), "kappa_min"},
      {run_path("/conjunctions?order_by=name1"), "order_by"},
      {run_path("/conjunctions?collisions_only=maybe"), "collisions_only"},
      {run_path("/conjunctions?format=xml"), "format"},
      {run_path("/conjunctions?page_token=zz"), "page_token"},
      {run_path("/conjunctions?colour=red"), "colour"},
      {run_path("/figures?compare=1,x"), "compare"},
      {"/api/runs?state=sleeping", "state"},
      {"/api/runs?page_size=-3", "page_size"},
      {"/api/runs/99999999999999999999999", "run_id"},
  };
  for (const auto& [path, parameter] : cases) {
    auto r = get(path);
    ASSERT_TRUE(r) << path;
    EXPECT_EQ(r->status, 400) << path;
    json body = json::parse(r->body);
    EXPECT_EQ(body.value("parameter", ""), parameter) << path << " " << r->body;
    EXPECT_FALSE(body.value("error", "").empty()) << path;
  }
}

TEST_F(Dashboard, UnknownPathsAndRunsAre404) {
  for (const std::string path : {"/nowhere", "/api/runs/1/nothing", "/api/runs/abc", "/api/runs/424242",
                                 "/api/runs/424242/conjunctions", "/api/ensembles/77", "/runs/x"}) {
    auto r = get(path);
    ASSERT_TRUE(r) << path;
    EXPECT_EQ(r->status, 404) << path;
    EXPECT_FALSE(json::parse(r->body).value("error", "").empty()) << path;
  }
}

TEST_F(Dashboard, PagesVisitEveryConjunctionOnce) {
  auto all = get(run_path("/conjunctions?include_evasions=true"));
  ASSERT_TRUE(all);
  const std::uint64_t total = json::parse(all->body)["total"];
  ASSERT_GT(total, 2u);
  std::set<std::uint64_t> seen;
  std::string token;
  int pages = 0;
  do {
    auto r = get(run_path("/conjunctions?include_evasions=true&page_size=2") +
                 (token.empty() ? "" : "&page_token=" + token));
    ASSERT_TRUE(r);
    ASSERT_EQ(r->status, 200) << r->body;
    json page = json::parse(r->body);
    EXPECT_LE(page["conjunctions"].size(), 2u);
    for (const json& c : page["conjunctions"]) EXPECT_TRUE(seen.insert(c["seq"].get<std::uint64_t>()).second);
    token = page["next_page_token"];
    ++pages;
  } while (!token.empty() && pages < 100);
  EXPECT_EQ(seen.size(), total);
  EXPECT_EQ(pages, static_cast<int>((total + 1) / 2));
}

TEST_F(Dashboard, ConjunctionsSortAndFilter) {
  auto r = get(run_path("/conjunctions?order_by=miss_distance_m&descending=true"));
  ASSERT_TRUE(r);
  json rows = json::parse(r->body)["conjunctions"];
  ASSERT_GT(rows.size(), 1u);
  for (std::size_t i = 1; i < rows.size(); ++i)
    EXPECT_GE(rows[i - 1]["miss_distance_m"].get<double>(), rows[i]["miss_distance_m"].get<double>());
  auto collisions = get(run_path("/conjunctions?collisions_only=true"));
  json c = json::parse(collisions->body);
  EXPECT_EQ(c["total"], 1);  // the pair aimed 3 m apart with radii 2 m + 2 m
  EXPECT_EQ(c["conjunctions"][0]["kind"], "collision");
}

TEST_F(Dashboard, CsvHoldsOneRowPerConjunction) {
  auto r = get(run_path("/conjunctions?format=csv"));
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 200);
  EXPECT_EQ(r->get_header_value("Content-Type"), "text/csv");
  const std::size_t lines = static_cast<std::size_t>(std::count(r->body.begin(), r->body.end(), '\n'));
  EXPECT_EQ(std::to_string(lines - 1), r->get_header_value("X-Total-Count"));
  EXPECT_EQ(r->body.rfind("seq,tca_s,id1,name1,id2,name2,miss_distance_m", 0), 0u);
}

TEST_F(Dashboard, PagesAndScriptsAreServed) {
  auto index = get("/");
  ASSERT_TRUE(index);
  EXPECT_EQ(index->status, 200);
  EXPECT_NE(index->body.find("/assets/charts.js"), std::string::npos);
  auto script = get("/assets/charts.js");
  ASSERT_TRUE(script);
  EXPECT_GT(script->body.size(), 500000u);  // vega, vega-lite and vega-embed, compiled in
  EXPECT_NE(script->body.find("kesslerRenderFigures"), std::string::npos);
  auto figures = get(run_path("/figures"));
  ASSERT_TRUE(figures);
  EXPECT_EQ(json::parse(figures->body)["figures"].size(), 8u);  // four from stats, four from snapshots
}

}  // namespace
}  // namespace kessler
