// Mass and momentum as core/breakup/README.md documents them, and no fragment with a non-finite or
// negative value.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "core/breakup/fragment_cloud.hpp"
#include "tests/breakup/reference.hpp"

namespace kessler {
namespace {

std::array<double, 3> parents_momentum(const BreakupEvent& e) {
  std::array<double, 3> p{};
  for (const BreakupParent& q : e.parents)
    for (int k = 0; k < 3; ++k) p[k] += q.mass_kg * q.velocity_m_s[k];
  return p;
}

const std::vector<double>& component(const Vec3Arrays& v, int k) {
  return k == 0 ? v.x : (k == 1 ? v.y : v.z);
}

std::vector<BreakupEvent> events() {
  std::vector<BreakupEvent> out;
  for (std::uint64_t id = 0; id < 12; ++id) {
    out.push_back(breakup_test::reference_collision(11700.0, 0.05, id));
    out.push_back(breakup_test::reference_collision(100.0, 0.05, id));
    out.push_back(breakup_test::reference_explosion(0.05, id));
  }
  return out;
}

TEST(BreakupConservation, FragmentsNeverOutweighTheParents) {
  int trimmed = 0;
  for (const BreakupEvent& e : events()) {
    const FragmentCloud c = generate_fragments(e);
    double sum = 0.0;
    for (double m : c.mass_kg) sum += m;
    EXPECT_DOUBLE_EQ(sum, c.fragment_mass_kg);
    EXPECT_LE(c.fragment_mass_kg, c.parent_mass_kg);
    const double remnant = c.remnant ? c.remnant->mass_kg : 0.0;
    EXPECT_NEAR(c.fragment_mass_kg + remnant + c.unresolved_mass_kg, c.parent_mass_kg,
                1e-9 * c.parent_mass_kg);
    EXPECT_GE(c.unresolved_mass_kg, -1e-9 * c.parent_mass_kg);
    if (c.size() < c.drawn_count) {
      ++trimmed;
      // Only the heaviest were dropped: against the same event drawn without conservation, the kept
      // fragments are the drawn ones unchanged and none is heavier than a dropped one.
      BreakupEvent free = e;
      free.conserve_mass = false;
      const FragmentCloud all = generate_fragments(free);
      ASSERT_GT(all.fragment_mass_kg, all.parent_mass_kg);
      double lightest_dropped = INFINITY, heaviest_kept = 0.0;
      std::size_t k = 0;
      for (std::size_t i = 0; i < all.size(); ++i) {
        if (k < c.size() && c.draw_index[k] == i) {
          heaviest_kept = std::max(heaviest_kept, all.mass_kg[i]);
          EXPECT_EQ(c.mass_kg[k], all.mass_kg[i]);
          ++k;
        } else {
          lightest_dropped = std::min(lightest_dropped, all.mass_kg[i]);
        }
      }
      EXPECT_EQ(k, c.size());
      EXPECT_GE(lightest_dropped, heaviest_kept);
    }
  }
  std::printf("%d of %zu clouds drew more mass than their parents and dropped their heaviest\n", trimmed,
              events().size());
  EXPECT_GT(trimmed, 0);  // the rule was exercised
}

TEST(BreakupConservation, NonCatastrophicMomentumIsExact) {
  for (std::uint64_t id = 0; id < 12; ++id) {
    const BreakupEvent e = breakup_test::reference_collision(100.0, 0.05, id);
    const FragmentCloud c = generate_fragments(e);
    ASSERT_TRUE(c.remnant.has_value());
    const auto p = parents_momentum(e);
    for (int k = 0; k < 3; ++k) {
      double sum = c.remnant->mass_kg * c.remnant->velocity_m_s[k];
      for (std::size_t i = 0; i < c.size(); ++i) sum += c.mass_kg[i] * component(c.velocity_m_s, k)[i];
      EXPECT_NEAR(sum, p[k], 1e-9 * 560.0 * 100.0) << "axis " << k;
    }
  }
}

// The fragments' mass-weighted mean velocity against the parents' (sum m v / sum m): the fragments keep
// their parent's velocity plus an isotropic dv, and each parent has its mass share of the fragments at
// every size, so the two agree in expectation. The standard error of the weighted mean is estimated
// from the sample (sum m_i^2 (v_i - V)^2 / (sum m_i)^2, an upper bound for the stratified assignment);
// the test allows 4 of it.
TEST(BreakupConservation, CatastrophicAndExplosionMomentumWithinSamplingNoise) {
  for (const BreakupEvent& e : events()) {
    const FragmentCloud c = generate_fragments(e);
    if (!c.catastrophic) continue;
    const auto p = parents_momentum(e);
    for (int k = 0; k < 3; ++k) {
      const double expected = p[k] / c.parent_mass_kg;
      double mv = 0.0, m2v2 = 0.0;
      for (std::size_t i = 0; i < c.size(); ++i) {
        const double d = component(c.velocity_m_s, k)[i] - expected;
        mv += c.mass_kg[i] * d;
        m2v2 += c.mass_kg[i] * c.mass_kg[i] * d * d;
      }
      const double offset = mv / c.fragment_mass_kg, standard_error = std::sqrt(m2v2) / c.fragment_mass_kg;
      EXPECT_LE(std::abs(offset), 4.0 * standard_error) << "event " << e.event_id << " axis " << k;
      if (e.event_id == 0 && k == 0)
        std::printf(
            "%s event 0, x: mass-weighted mean velocity %+.1f m/s from the parents' (standard error "
            "%.1f m/s)\n",
            e.kind == BreakupKind::kExplosion ? "explosion" : "catastrophic collision", offset,
            standard_error);
    }
  }
}

TEST(BreakupConservation, FragmentsFollowTheirParent) {
  const BreakupEvent e = breakup_test::reference_collision(11700.0, 0.05, 3);
  const FragmentCloud c = generate_fragments(e);
  std::size_t from_projectile = 0;
  for (std::size_t i = 0; i < c.size(); ++i) {
    const BreakupParent& p = e.parents[c.parent_index[i]];
    from_projectile += c.parent_index[i] == 0;
    EXPECT_DOUBLE_EQ(c.velocity_m_s.x[i], p.velocity_m_s[0] + c.delta_v_m_s.x[i]);
    EXPECT_DOUBLE_EQ(c.velocity_m_s.y[i], p.velocity_m_s[1] + c.delta_v_m_s.y[i]);
    EXPECT_DOUBLE_EQ(c.position_m.x[i], p.position_m[0]);
    EXPECT_DOUBLE_EQ(c.radius_m[i], 0.5 * c.characteristic_length_m[i]);
  }
  // 560 / 1510 of the strata go to the projectile: exact to one fragment, less any dropped by mass
  // conservation.
  EXPECT_NEAR(static_cast<double>(from_projectile), c.drawn_count * 560.0 / 1510.0,
              1.0 + static_cast<double>(c.drawn_count - c.size()));
}

TEST(BreakupConservation, NoNonFiniteOrNegativeValues) {
  for (BreakupEvent e : events()) {
    e.min_characteristic_length_m = 0.01;
    const FragmentCloud c = generate_fragments(e);
    for (std::size_t i = 0; i < c.size(); ++i) {
      for (double v : {c.characteristic_length_m[i], c.area_to_mass_m2_kg[i], c.area_m2[i], c.mass_kg[i],
                       c.radius_m[i]}) {
        ASSERT_TRUE(std::isfinite(v));
        ASSERT_GT(v, 0.0);
      }
      for (const Vec3Arrays* v : {&c.delta_v_m_s, &c.velocity_m_s, &c.position_m})
        ASSERT_TRUE(std::isfinite(v->x[i]) && std::isfinite(v->y[i]) && std::isfinite(v->z[i]));
    }
    if (c.remnant) {
      EXPECT_GT(c.remnant->mass_kg, 0.0);
      for (double v : c.remnant->velocity_m_s) EXPECT_TRUE(std::isfinite(v));
    }
  }
}

}  // namespace
}  // namespace kessler
