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
