#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "core/population/population.hpp"

namespace kessler {
namespace {

ObjectRecord sound_object(ObjectId id) {
  ObjectRecord r;
  r.id = id;
  r.name = "OBJ " + std::to_string(id);
  r.position_m = {7.0e6, 0.0, 0.0};
  r.velocity_m_s = {0.0, 7.5e3, 0.0};
  r.radius_m = 0.5;
  r.mass_kg = 100.0;
  r.drag_area_to_mass_m2_kg = 0.01;
  r.srp_area_to_mass_m2_kg = 0.005;
  return r;
}

TEST(Population, RemovalKeepsIdsAndOrderOfTheRest) {
  Population p;
  for (ObjectId id = 10; id < 15; ++id) p.add(sound_object(id));
  p.remove_flagged({0, 1, 0, 1, 0});
  ASSERT_EQ(p.size(), 3u);
  EXPECT_EQ(p.id, (std::vector<ObjectId>{10, 12, 14}));
  EXPECT_EQ(p.name[1], "OBJ 12");
  EXPECT_EQ(p.state.size(), 3u);
}

TEST(Population, RemovalAtTheEndsAndInRunsMovesEveryColumn) {
  // 21 objects (not a multiple of the 8 flags read at once); removed: the first, a run of three, one
  // in the last partial group of eight and the last. Every column of the rest must follow its id.
  Population p;
  for (ObjectId id = 0; id < 21; ++id) {
    ObjectRecord r = sound_object(id);
    r.position_m.y() = static_cast<double>(id);
    r.velocity_m_s.z() = -static_cast<double>(id);
    r.radius_m = 1.0 + static_cast<double>(id);
    r.mass_kg = 10.0 * (1.0 + static_cast<double>(id));
    r.drag_area_to_mass_m2_kg = 0.001 * static_cast<double>(id);
    r.srp_area_to_mass_m2_kg = 0.002 * static_cast<double>(id);
    r.status = id % 2 ? ObjectStatus::kActive : ObjectStatus::kPassive;
    p.add(r);
  }
  std::vector<char> flags(21, 0);
  for (std::size_t i : {0, 5, 6, 7, 17, 20}) flags[i] = 1;
  p.remove_flagged(flags);
  const std::vector<ObjectId> kept = {1, 2, 3, 4, 8, 9, 10, 11, 12, 13, 14, 15, 16, 18, 19};
  ASSERT_EQ(p.id, kept);
  ASSERT_EQ(p.size(), kept.size());
  for (std::size_t i = 0; i < kept.size(); ++i) {
    const ObjectRecord r = p.record(i);
    const double id = static_cast<double>(kept[i]);
    EXPECT_EQ(r.name, "OBJ " + std::to_string(kept[i]));
    EXPECT_EQ(r.position_m.y(), id);
    EXPECT_EQ(r.velocity_m_s.z(), -id);
    EXPECT_EQ(r.radius_m, 1.0 + id);
    EXPECT_EQ(r.mass_kg, 10.0 * (1.0 + id));
    EXPECT_EQ(r.drag_area_to_mass_m2_kg, 0.001 * id);
    EXPECT_EQ(r.srp_area_to_mass_m2_kg, 0.002 * id);
    EXPECT_EQ(r.status, kept[i] % 2 ? ObjectStatus::kActive : ObjectStatus::kPassive);
  }
  p.remove_flagged(std::vector<char>(kept.size(), 0));  // nothing flagged: nothing changes
  EXPECT_EQ(p.id, kept);
}

TEST(Population, ValidationNamesObjectAndField) {
  auto bad = sound_object(7);
  bad.position_m.x() = std::numeric_limits<double>::quiet_NaN();
  auto problem = validate_record(bad);
  ASSERT_TRUE(problem);
  EXPECT_EQ(*problem, "object 7 (OBJ 7): position is not finite");

  bad = sound_object(8);
  bad.radius_m = -1.0;
  EXPECT_EQ(*validate_record(bad), "object 8 (OBJ 8): radius_m must be positive");

  bad = sound_object(9);
  bad.position_m = {1.0e6, 0.0, 0.0};
  EXPECT_EQ(*validate_record(bad), "object 9 (OBJ 9): position is below the Earth's surface");

  Population p;
  p.add(sound_object(1));
  p.add(sound_object(1));
  EXPECT_EQ(*p.validate(), "object 1: id is not unique");
}

}  // namespace
}  // namespace kessler
