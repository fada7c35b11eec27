// Conjunctions with their collision probability, as the daemon lists them: pc fields on every listed
// conjunction (the core's assessment of the stored states), the pc filter, the sorts and their paging,
// one conjunction by sequence number and its CDM (read back by the CDM reader).
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <stdexcept>

#include "core/assessment/assess_encounter.hpp"
#include "core/assessment/cdm.hpp"
#include "core/assessment/cdm_conjunction.hpp"
#include "server/conjunction_assessment.hpp"
#include "server/store.hpp"
#include "tests/service/temp_dir.hpp"

namespace kessler::server {
namespace {

void set(v1::Vector3* out, double x, double y, double z) {
  out->set_x(x);
  out->set_y(y);
  out->set_z(z);
}

// Two objects crossing at right angles in a 7,000 km orbit, the second `miss_m` further out; r1 + r2 10 m.
std::shared_ptr<const v1::RunEvent> crossing(std::int64_t run, std::uint64_t seq, double miss_m) {
  auto e = std::make_shared<v1::RunEvent>();
  e->set_run_id(run);
  e->set_seq(seq);
  auto* c = e->mutable_encounter();
  c->set_id1(10 + seq);
  c->set_id2(20 + seq);
  c->set_tca_s(60.0 * static_cast<double>(seq));
  c->set_miss_distance_m(miss_m);
  c->set_kappa(miss_m / 10.0);
  c->set_relative_speed_m_s(7500.0 * std::sqrt(2.0));
  c->set_kind(v1::ENCOUNTER_KIND_CONJUNCTION);
  c->set_seq(seq);
  set(c->mutable_r1_m(), 7.0e6, 0.0, 0.0);
  set(c->mutable_v1_m_s(), 0.0, 7500.0, 0.0);
  set(c->mutable_r2_m(), 7.0e6 + miss_m, 0.0, 0.0);
  set(c->mutable_v2_m_s(), 0.0, 0.0, 7500.0);
  return e;
}

class AssessedListing : public ::testing::Test {
 protected:
  void SetUp() override {
    run_ = store_.create_run(v1::Scenario(), 1, 0.0);
    store_.set_object_names(run_, {{11, "COSMOS 2251 DEB"}, {21, "IRIDIUM 33"}});
    const double misses[] = {4000.0, 150.0, 2500.0, 900.0, 60.0, 3000.0};
    for (std::uint64_t seq = 1; seq <= 6; ++seq) store_.append_event(crossing(run_, seq, misses[seq - 1]));
    store_.flush();
  }
  v1::ListConjunctionsRequest request() const {
    v1::ListConjunctionsRequest r;
    r.set_run_id(run_);
    return r;
  }
  TempDir dir_;
  Store store_{dir_.path() + "/k.db"};
  std::int64_t run_ = 0;
};

TEST_F(AssessedListing, EveryConjunctionCarriesItsAssessment) {
  const v1::ListConjunctionsResponse r = assessed_conjunctions(store_, request());
  ASSERT_EQ(r.conjunctions_size(), 6);
  for (const auto& c : r.conjunctions()) {
    ASSERT_TRUE(c.has_pc()) << c.seq();
    EXPECT_GT(c.pc(), 0.0);
    EXPECT_LT(c.pc(), 1.0);
    EXPECT_EQ(c.covariance_source(), "model");
    EXPECT_TRUE(c.pc_method() == "chan" || c.pc_method() == "foster");
    EXPECT_TRUE(c.has_pc_max());
    EXPECT_GT(c.pc_max_sigma_m(), 0.0);
    EXPECT_TRUE(c.short_encounter());
  }
  // The objects' types come from their names (debris, payload): the first event's pc is the core's for
  // those types.
  const auto& first = r.conjunctions(0);
  EXPECT_EQ(first.name1(), "COSMOS 2251 DEB");
  Encounter e;
  e.tca_s = first.tca_s();
  e.miss_distance_m = first.miss_distance_m();
  e.kappa = first.kappa();
  e.r1_m = {7.0e6, 0.0, 0.0};
  e.v1_m_s = {0.0, 7500.0, 0.0};
  e.r2_m = {7.0e6 + 4000.0, 0.0, 0.0};
  e.v2_m_s = {0.0, 0.0, 7500.0};
  const auto a = assessment::assess_encounter(e, {ObjectType::kDebris, 0.0}, {ObjectType::kPayload, 0.0});
  EXPECT_DOUBLE_EQ(first.pc(), a.pc);
}

TEST_F(AssessedListing, FiltersByPcAndSortsLargestFirstAcrossPages) {
  v1::ListConjunctionsRequest r = request();
  r.set_sort("pc");
  const v1::ListConjunctionsResponse all = assessed_conjunctions(store_, r);
  ASSERT_EQ(all.conjunctions_size(), 6);
  for (int i = 1; i < 6; ++i) EXPECT_GE(all.conjunctions(i - 1).pc(), all.conjunctions(i).pc());
  EXPECT_EQ(all.conjunctions(0).seq(), 5u);  // the 60 m miss
  const double threshold = all.conjunctions(2).pc();
  r.set_pc_min(threshold);
  r.set_page_size(2);
  v1::ListConjunctionsResponse page = assessed_conjunctions(store_, r);
  EXPECT_EQ(page.total(), 3u);
  ASSERT_EQ(page.conjunctions_size(), 2);
  EXPECT_EQ(page.conjunctions(0).seq(), all.conjunctions(0).seq());
  r.set_page_token(page.next_page_token());
  page = assessed_conjunctions(store_, r);
  ASSERT_EQ(page.conjunctions_size(), 1);
  EXPECT_EQ(page.conjunctions(0).seq(), all.conjunctions(2).seq());
  EXPECT_TRUE(page.next_page_token().empty());
  r = request();
  r.set_sort("miss");
  EXPECT_EQ(assessed_conjunctions(store_, r).conjunctions(0).seq(), 5u);
}

TEST_F(AssessedListing, RefusesABadSortOrPcMinNamingTheField) {
  v1::ListConjunctionsRequest r = request();
  r.set_sort("probability");
  try {
    assessed_conjunctions(store_, r);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()).rfind("sort:", 0), 0u) << e.what();
  }
  r = request();
  r.set_pc_min(1.5);
  EXPECT_THROW(assessed_conjunctions(store_, r), std::invalid_argument);
}

TEST_F(AssessedListing, OneConjunctionAsACdmThatReadsBack) {
  EXPECT_FALSE(store_.conjunction(run_, 99).has_value());
  const std::optional<v1::Encounter> e = store_.conjunction(run_, 1);
  ASSERT_TRUE(e.has_value());
  EXPECT_EQ(e->name1(), "COSMOS 2251 DEB");
  v1::Encounter listed = *e;
  fill_assessment(listed);
  for (const std::string format : {"kvn", "xml"}) {
    const v1::ConjunctionCdm cdm =
        conjunction_cdm(*e, run_, UtcEpoch::from_calendar(2022, 1, 22, 0, 0, 0.0), format);
    EXPECT_EQ(cdm.file_name(), format == "xml" ? "run1_seq1.xml" : "run1_seq1.cdm");
    assessment::Cdm parsed;
    std::vector<assessment::CdmError> errors;
    ASSERT_TRUE(assessment::read_cdm(cdm.text(), parsed, errors));
    assessment::CdmConjunction c;
    EXPECT_TRUE(assessment::read_conjunction(parsed, c, errors));
    EXPECT_TRUE(errors.empty()) << errors.front().message;
    EXPECT_EQ(c.tca, "2022-01-22T00:01:00.000000");
    EXPECT_EQ(c.objects[0].name, "COSMOS 2251 DEB");
    ASSERT_TRUE(c.cdm_pc.has_value());
    EXPECT_NEAR(*c.cdm_pc / listed.pc(), 1.0, 1e-6);
  }
  EXPECT_THROW(conjunction_cdm(*e, run_, UtcEpoch(), "json"), std::invalid_argument);
}

}  // namespace
}  // namespace kessler::server
