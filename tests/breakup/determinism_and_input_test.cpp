// The same event gives the same bits on any thread count; other event ids give other clouds; bad input
// is a BreakupInputError naming the field, before anything is allocated.
#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>
#include <cstring>
#include <limits>

#include "core/breakup/fragment_cloud.hpp"
#include "tests/breakup/reference.hpp"

namespace kessler {
namespace {

template <typename T>
bool same_bits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0;
}

bool same_bits(const FragmentCloud& a, const FragmentCloud& b) {
  bool same = same_bits(a.draw_index, b.draw_index) && same_bits(a.parent_index, b.parent_index) &&
              same_bits(a.characteristic_length_m, b.characteristic_length_m) &&
              same_bits(a.area_to_mass_m2_kg, b.area_to_mass_m2_kg) && same_bits(a.area_m2, b.area_m2) &&
              same_bits(a.mass_kg, b.mass_kg) && same_bits(a.radius_m, b.radius_m);
  for (auto v : {&FragmentCloud::delta_v_m_s, &FragmentCloud::velocity_m_s, &FragmentCloud::position_m})
    same = same && same_bits((a.*v).x, (b.*v).x) && same_bits((a.*v).y, (b.*v).y) &&
           same_bits((a.*v).z, (b.*v).z);
  same = same && std::memcmp(&a.fragment_mass_kg, &b.fragment_mass_kg, sizeof(double)) == 0;
  same = same && a.remnant.has_value() == b.remnant.has_value();
  if (a.remnant && b.remnant)
    same = same && std::memcmp(a.remnant->velocity_m_s.data(), b.remnant->velocity_m_s.data(), 24) == 0 &&
           std::memcmp(&a.remnant->mass_kg, &b.remnant->mass_kg, sizeof(double)) == 0;
  return same;
}

TEST(BreakupDeterminism, SameBitsOnOneTwoAndFourThreads) {
  const int before = omp_get_max_threads();
  for (const BreakupEvent& e :
       {breakup_test::reference_collision(11700.0, 0.01, 7),
        breakup_test::reference_collision(100.0, 0.01, 7), breakup_test::reference_explosion(0.01, 7),
        breakup_test::reference_collision(11700.0, 0.05, 0)}) {
    omp_set_num_threads(1);
    const FragmentCloud one = generate_fragments(e);
    for (int threads : {2, 4}) {
      omp_set_num_threads(threads);
      EXPECT_TRUE(same_bits(one, generate_fragments(e))) << threads << " threads, event " << e.event_id;
    }
    // Reusing a cloud's arrays gives the same bits as a fresh cloud.
    FragmentCloud reused = generate_fragments(breakup_test::reference_explosion(0.02, 99));
    generate_fragments(e, reused);
    EXPECT_TRUE(same_bits(one, reused));
  }
  omp_set_num_threads(before);
}

TEST(BreakupDeterminism, OtherEventIdsAndSeedsGiveOtherClouds) {
  const BreakupEvent a = breakup_test::reference_collision(11700.0, 0.05, 1);
  BreakupEvent b = a, s = a;
  b.event_id = 2;
  s.seed += 1;
  const FragmentCloud ca = generate_fragments(a), cb = generate_fragments(b), cs = generate_fragments(s);
  for (const FragmentCloud* other : {&cb, &cs}) {
    ASSERT_EQ(ca.drawn_count, other->drawn_count);
    const std::size_t n = std::min(ca.size(), other->size());
    std::size_t equal_am = 0, equal_dv = 0;
    for (std::size_t i = 0; i < n; ++i) {
      equal_am += ca.area_to_mass_m2_kg[i] == other->area_to_mass_m2_kg[i];
      equal_dv += ca.delta_v_m_s.x[i] == other->delta_v_m_s.x[i];
    }
    EXPECT_EQ(equal_am, 0u);
    EXPECT_EQ(equal_dv, 0u);
  }
}

BreakupEvent valid() {
  return breakup_test::reference_collision(11700.0, 0.1, 1);
}

void expect_field(const BreakupEvent& e, const std::string& field) {
  try {
    generate_fragments(e);
    ADD_FAILURE() << "no error for " << field;
  } catch (const BreakupInputError& error) {
    EXPECT_EQ(error.field(), field) << error.what();
    EXPECT_NE(std::string(error.what()).find(field), std::string::npos);
  }
}

TEST(BreakupInput, BadValuesNameTheirField) {
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  BreakupEvent e = valid();
  e.parents[0].mass_kg = -1.0;
  expect_field(e, "parents[0].mass_kg");
  e = valid();
  e.parents[1].mass_kg = nan;
  expect_field(e, "parents[1].mass_kg");
  e = valid();
  e.parents[1].characteristic_length_m = 0.0;
  expect_field(e, "parents[1].characteristic_length_m");
  e = valid();
  e.parents[0].velocity_m_s[2] = inf;
  expect_field(e, "parents[0].velocity_m_s");
  e = valid();
  e.parents[0].position_m[0] = nan;
  expect_field(e, "parents[0].position_m");
  e = valid();
  e.impact_speed_m_s = -5.0;
  expect_field(e, "impact_speed_m_s");
  e = valid();
  e.impact_speed_m_s = nan;
  expect_field(e, "impact_speed_m_s");
  for (double lc : {0.0, -0.1, 1.5, nan}) {
    e = valid();
    e.min_characteristic_length_m = lc;
    expect_field(e, "min_characteristic_length_m");
  }
  e = valid();
  e.parents.pop_back();
  expect_field(e, "parents");
  e = breakup_test::reference_explosion(0.1, 1);
  e.explosion_scale = -1.0;
  expect_field(e, "explosion_scale");
  e = breakup_test::reference_explosion(0.1, 1);
  e.impact_speed_m_s = 100.0;
  expect_field(e, "impact_speed_m_s");
}

TEST(BreakupInput, TooManyFragmentsIsAnErrorNotAnAllocation) {
  // 1 mm from a 1,510 kg catastrophic collision: 3.3e6 fragments, above the default 1e6.
  BreakupEvent e = breakup_test::reference_collision(11700.0, 0.001, 1);
  expect_field(e, "max_fragments_per_event");
  // Masses whose count overflows to infinity, or a scale of 1e300, fail the same way.
  e = valid();
  e.parents[0].mass_kg = e.parents[1].mass_kg = 1e308;
  expect_field(e, "max_fragments_per_event");
  e = breakup_test::reference_explosion(0.1, 1, 1e300);
  expect_field(e, "max_fragments_per_event");
  // A lower limit applies as given.
  e = breakup_test::reference_explosion(0.05, 1);
  e.max_fragments_per_event = 100;
  expect_field(e, "max_fragments_per_event");
  e.max_fragments_per_event = 724;
  EXPECT_EQ(generate_fragments(e).drawn_count, 724u);
  // An error leaves a reused cloud as it was.
  FragmentCloud cloud = generate_fragments(e);
  e.max_fragments_per_event = 100;
  EXPECT_THROW(generate_fragments(e, cloud), BreakupInputError);
  EXPECT_EQ(cloud.drawn_count, 724u);
}

TEST(BreakupInput, EdgeCasesGiveValidClouds) {
  // Parents no larger than Lc_min: no fragment (the non-catastrophic target survives whole).
  BreakupEvent e = breakup_test::reference_collision(100.0, 0.5, 1);
  e.parents[0].characteristic_length_m = e.parents[1].characteristic_length_m = 0.4;
  FragmentCloud c = generate_fragments(e);
  EXPECT_EQ(c.size(), 0u);
  ASSERT_TRUE(c.remnant.has_value());
  EXPECT_DOUBLE_EQ(c.remnant->mass_kg, 1510.0);
  // Zero impact speed, zero explosion scale: no fragments.
  e = valid();
  e.impact_speed_m_s = 0.0;
  EXPECT_EQ(generate_fragments(e).size(), 0u);
  e = breakup_test::reference_explosion(0.1, 1, 0.0);
  EXPECT_EQ(generate_fragments(e).size(), 0u);
}

}  // namespace
}  // namespace kessler
