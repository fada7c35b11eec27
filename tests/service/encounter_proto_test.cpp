// The Encounter -> kessler.v1.Encounter conversion (for_each_field's third user) carries every field.
#include <gtest/gtest.h>

#include <cmath>

#include "server/run_manager.hpp"

namespace kessler::server {
namespace {

TEST(EncounterProto, CarriesEveryField) {
  Encounter e;
  e.id1 = 11;
  e.id2 = 22;
  e.tca_s = 1.0 / 3.0;
  e.miss_distance_m = 4.5;
  e.relative_speed_m_s = 7000.25;
  e.kappa = 0.125;
  e.kind = EncounterKind::kEvasion;
  e.r1_m = {1, 2, 3};
  e.v1_m_s = {4, 5, 6};
  e.r2_m = {7, 8, 9};
  e.v2_m_s = {10, 11, -0.0};
  const v1::Encounter p = to_proto(e);
  EXPECT_EQ(p.id1(), 11u);
  EXPECT_EQ(p.id2(), 22u);
  EXPECT_EQ(p.tca_s(), 1.0 / 3.0);
  EXPECT_EQ(p.miss_distance_m(), 4.5);
  EXPECT_EQ(p.relative_speed_m_s(), 7000.25);
  EXPECT_EQ(p.kappa(), 0.125);
  EXPECT_EQ(p.kind(), v1::ENCOUNTER_KIND_EVASION);
  EXPECT_EQ(p.r1_m().x(), 1.0);
  EXPECT_EQ(p.r1_m().y(), 2.0);
  EXPECT_EQ(p.r1_m().z(), 3.0);
  EXPECT_EQ(p.v1_m_s().x(), 4.0);
  EXPECT_EQ(p.r2_m().y(), 8.0);
  EXPECT_EQ(p.v2_m_s().y(), 11.0);
  EXPECT_TRUE(std::signbit(p.v2_m_s().z()));
  EXPECT_EQ(p.seq(), 0u);  // the relay sets the sequence number
}

}  // namespace
}  // namespace kessler::server
