// The real catalog (3LE 2022-01-22 with the Space-Track SATCAT and the CelesTrak active list) ingested
// to 2022-01-01 with the paper's rules. Every expected figure below comes from an independent route:
//
//   /usr/bin/python3 tests/population/independent_catalog_check.py
//
// (Python standard library + Debian's python3-sgp4, i.e. Vallado's SGP4 in its official Python port;
// the counter-based radius draws re-implemented there from the documented spec.) Its output:
//   records 23939 rejected 0 accepted 23939
//   filtered docked 7 / excluded name 2242 / perigee below band 54 / apogee above band 4852 / SGP4 failed 57
//     / decayed before the start 9
//   kept 16718 active 958 passive 15760
//   active median radius 0.468438363 mass 41.994229560 sma 7016.370041
//   passive median radius 0.125536305 mass 2.141577399 sma 7192.373009
//   state 22675 -1908.165110 515.533900 6864.590468 -2.668651137 -6.976880642 -0.232106653
//   state 43013 -3493.813518 6100.355905 -1594.902914 1.809909984 -0.828880442 -7.165518501
#include <gtest/gtest.h>

#include <cstdio>

#include "core/catalog/bundled_datasets.hpp"

namespace kessler {
namespace {

class Catalog2022 : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    std::string error;
    auto input =
        load_bundled_catalog("catalog-2022", std::string(KESSLER_REPO_DIR) + "/deploy/datasets", &error);
    ASSERT_TRUE(input) << error;
    result_ = new IngestResult(
        ingest_catalog(*input, IngestRules{}, UtcEpoch::from_calendar(2022, 1, 1, 0, 0, 0), 1));
    std::printf("%s", result_->report.text(5).c_str());
  }
  static void TearDownTestSuite() {
    delete result_;
    result_ = nullptr;
  }
  static IngestResult* result_;
};
IngestResult* Catalog2022::result_ = nullptr;

TEST_F(Catalog2022, CountsMatchTheIndependentRoute) {
  const IngestReport& r = result_->report;
  ASSERT_FALSE(result_->refused);
  EXPECT_EQ(r.records, 23939u);
  EXPECT_EQ(r.accepted, 23939u);
  EXPECT_EQ(r.rejected, 0u);
  // Soyuz MS-19, Progress MS-18, two Dragons (ISS), Tianzhou 3, Shenzhou 13 (Tiangong), MEV-2 (GEO).
  EXPECT_EQ(r.filtered("docked"), 7u);
  EXPECT_EQ(r.filtered("excluded name"), 2242u);
  EXPECT_EQ(r.filtered("perigee below band"), 54u);
  EXPECT_EQ(r.filtered("apogee above band"), 4852u);
  EXPECT_EQ(r.filtered("SGP4 failed"), 57u);
  EXPECT_EQ(r.propagation_failures.size(), 57u);
  // Element sets older than their decay: SGP4 puts them below the 150 km burn-up altitude at the start.
  EXPECT_EQ(r.filtered("decayed before the start"), 9u);
  EXPECT_EQ(r.kept, 16718u);
  EXPECT_EQ(result_->population.size(), 16718u);
  EXPECT_EQ(r.active, 958u);
  EXPECT_EQ(r.passive, 15760u);
  // About 16,800 objects lie in the band by mean elements (shared README): kept plus SGP4 failures and
  // the decayed.
  EXPECT_NEAR(
      static_cast<double>(r.kept + r.filtered("SGP4 failed") + r.filtered("decayed before the start")),
      16800.0, 100.0);
  EXPECT_FALSE(result_->population.validate().has_value());
}

// Every record is accounted for once: kept, rejected or filtered (SGP4 failures are listed one by one in
// propagation_failures and counted in filtered_by_reason under "SGP4 failed" or "invalid state").
TEST_F(Catalog2022, EveryRecordIsKeptRejectedOrFiltered) {
  const IngestReport& r = result_->report;
  std::size_t rejected = 0, filtered = 0;
  for (const auto& [reason, n] : r.rejected_by_reason) rejected += n;
  for (const auto& [reason, n] : r.filtered_by_reason) filtered += n;
  EXPECT_EQ(rejected, r.rejected);
  EXPECT_EQ(r.records, r.accepted + r.rejected);
  EXPECT_EQ(r.records, r.kept + rejected + filtered);
  EXPECT_EQ(r.propagation_failures.size(), r.filtered("SGP4 failed") + r.filtered("invalid state"));
}

TEST_F(Catalog2022, SummaryStatisticsMatchTheIndependentRoute) {
  const IngestReport& r = result_->report;
  EXPECT_NEAR(r.active_summary.median_radius_m, 0.468438363, 1e-8);
  EXPECT_NEAR(r.active_summary.median_mass_kg, 41.994229560, 1e-6);
  EXPECT_NEAR(r.active_summary.median_semi_major_axis_km, 7016.370041, 1e-5);
  EXPECT_NEAR(r.passive_summary.median_radius_m, 0.125536305, 1e-8);
  EXPECT_NEAR(r.passive_summary.median_mass_kg, 2.141577399, 1e-8);
  EXPECT_NEAR(r.passive_summary.median_semi_major_axis_km, 7192.373009, 1e-5);
}

TEST_F(Catalog2022, StatesAtTheStartEpochMatchTheIndependentSgp4) {
  const Population& p = result_->population;
  struct Expected {
    ObjectId id;
    double r_km[3], v_km_s[3];
  };
  const Expected expected[] = {
      {22675, {-1908.165110, 515.533900, 6864.590468}, {-2.668651137, -6.976880642, -0.232106653}},
      {43013, {-3493.813518, 6100.355905, -1594.902914}, {1.809909984, -0.828880442, -7.165518501}},
  };
  for (const auto& e : expected) {
    auto i = p.index_of(e.id);
    ASSERT_TRUE(i) << e.id;
    for (int k = 0; k < 3; ++k) {
      // The independent route prints mm and um/s; time arithmetic differs in the last bits.
      EXPECT_NEAR(p.state.position(*i)[k], e.r_km[k] * 1000.0, 0.01) << e.id;
      EXPECT_NEAR(p.state.velocity(*i)[k], e.v_km_s[k] * 1000.0, 1e-5) << e.id;
    }
  }
}

TEST_F(Catalog2022, PropertiesFollowTheRules) {
  const Population& p = result_->population;
  for (std::size_t i = 0; i < p.size(); ++i) {
    ASSERT_GE(p.radius_m[i], 0.005);
    ASSERT_NEAR(p.mass_kg[i], mass_from_radius_kg(p.radius_m[i]), 1e-12 * p.mass_kg[i]);
    ASSERT_NEAR(p.srp_area_to_mass_m2_kg[i],
                3.14159265358979323846 * p.radius_m[i] * p.radius_m[i] / p.mass_kg[i],
                1e-12 * p.srp_area_to_mass_m2_kg[i]);
    const double bstar = result_->elements[i].bstar_per_earth_radius;
    if (bstar > 0.0) {
      ASSERT_NEAR(p.drag_area_to_mass_m2_kg[i], 2.0 * bstar / 0.15696615, 1e-15);
    }
  }
}

TEST(Catalog2022Determinism, SameSeedSamePopulationOtherSeedOtherRadii) {
  std::string error;
  auto input =
      load_bundled_catalog("catalog-2022", std::string(KESSLER_REPO_DIR) + "/deploy/datasets", &error);
  ASSERT_TRUE(input) << error;
  IngestRules rules;
  rules.max_objects = 500;
  const UtcEpoch start = UtcEpoch::from_calendar(2022, 1, 1, 0, 0, 0);
  const auto a = ingest_catalog(*input, rules, start, 7);
  const auto b = ingest_catalog(*input, rules, start, 7);
  const auto c = ingest_catalog(*input, rules, start, 8);
  ASSERT_EQ(a.population.size(), 500u);
  EXPECT_EQ(a.report.filtered("max objects"), 16718u - 500u);
  EXPECT_EQ(a.population.radius_m, b.population.radius_m);
  EXPECT_EQ(a.population.state.x, b.population.state.x);
  EXPECT_NE(a.population.radius_m, c.population.radius_m);
  EXPECT_EQ(a.population.state.x, c.population.state.x);
}

}  // namespace
}  // namespace kessler
