// Area-to-mass and ejection-velocity draws against the model's densities: Kolmogorov-Smirnov tests of the
// probability integral transform (each fragment's value through its own model CDF given its size and
// A/m, which is uniform when the draws follow the model) per size band, at significance 0.001 with fixed
// seeds. The CDFs come from tests/breakup/reference.hpp, written from the paper, not from core/breakup/.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "core/breakup/fragment_cloud.hpp"
#include "tests/breakup/reference.hpp"

namespace kessler {
namespace {

using breakup_test::area_to_mass_cdf;
using breakup_test::ejection_speed_cdf;
using breakup_test::ks_critical;
using breakup_test::ks_uniform;

struct Band {
  double lo, hi;  // m
};

const std::vector<Band> kBands = {{0.01, 0.03}, {0.03, 0.08}, {0.08, 0.11},
                                  {0.11, 0.3},  {0.3, 1.0},   {1.0, 4.0}};

// Fragments of several events of one kind (drawn without mass conservation, so that no size is favoured).
FragmentCloud pooled(BreakupEvent event, int events) {
  event.conserve_mass = false;
  FragmentCloud all;
  for (int k = 0; k < events; ++k) {
    event.event_id = 100 + static_cast<std::uint64_t>(k);
    const FragmentCloud c = generate_fragments(event);
    for (std::size_t i = 0; i < c.size(); ++i) {
      all.characteristic_length_m.push_back(c.characteristic_length_m[i]);
      all.area_to_mass_m2_kg.push_back(c.area_to_mass_m2_kg[i]);
      all.parent_index.push_back(c.parent_index[i]);
      all.delta_v_m_s.x.push_back(c.delta_v_m_s.x[i]);
      all.delta_v_m_s.y.push_back(c.delta_v_m_s.y[i]);
      all.delta_v_m_s.z.push_back(c.delta_v_m_s.z[i]);
    }
  }
  return all;
}

// KS statistics of A/m (and of dv) per band; fails a band whose statistic passes the critical value.
void check_bands(const FragmentCloud& c, const BreakupEvent& event, const char* name) {
  for (const Band& band : kBands) {
    std::vector<double> am, dv;
    for (std::size_t i = 0; i < c.characteristic_length_m.size(); ++i) {
      const double lc = c.characteristic_length_m[i];
      if (lc < band.lo || lc >= band.hi) continue;
      const double chi = std::log10(c.area_to_mass_m2_kg[i]);
      const BreakupObjectClass cls = event.parents[c.parent_index[i]].object_class;
      am.push_back(area_to_mass_cdf(chi, lc, cls));
      const double speed = std::hypot(c.delta_v_m_s.x[i], c.delta_v_m_s.y[i], c.delta_v_m_s.z[i]);
      dv.push_back(ejection_speed_cdf(std::log10(speed), chi, event.kind));
    }
    if (am.size() < 200) continue;
    const double d_am = ks_uniform(am), d_dv = ks_uniform(dv), crit = ks_critical(am.size());
    std::printf("%s Lc [%.2f, %.2f) m: n %zu, KS A/m %.4f, dv %.4f (critical %.4f)\n", name, band.lo, band.hi,
                am.size(), d_am, d_dv, crit);
    EXPECT_LT(d_am, crit) << name << " A/m, band from " << band.lo << " m";
    EXPECT_LT(d_dv, crit) << name << " dv, band from " << band.lo << " m";
  }
}

TEST(BreakupDistribution, SpacecraftCollisionAreaToMassAndSpeed) {
  // 63,713 fragments per event down to 1 cm; two events.
  BreakupEvent event = breakup_test::reference_collision(11700.0, 0.01, 0);
  check_bands(pooled(event, 2), event, "spacecraft collision");
}

TEST(BreakupDistribution, SpacecraftCollisionLargeFragments) {
  // The 8-11 cm bridge and the bimodal law above it: 24 events of 1,820 fragments down to 8 cm give
  // 1.8e4 in the bridge and 6e3 above 30 cm.
  BreakupEvent event = breakup_test::reference_collision(11700.0, 0.08, 0);
  check_bands(pooled(event, 24), event, "spacecraft collision, Lc >= 8 cm");
}

TEST(BreakupDistribution, RocketBodyExplosionAreaToMassAndSpeed) {
  // S = 5 gives 4.8e4 fragments down to 1 cm; S = 100, 7.2e4 down to 5 cm (2.0e4 above 11 cm): enough to see
  // the rocket-body bimodal law band by band.
  BreakupEvent event = breakup_test::reference_explosion(0.01, 0, 5.0);
  check_bands(pooled(event, 1), event, "rocket-body explosion (S 5)");
  event = breakup_test::reference_explosion(0.05, 0, 100.0);
  check_bands(pooled(event, 1), event, "rocket-body explosion (S 100)");
}

TEST(BreakupDistribution, RocketBodyCollisionUsesEachParentsClass) {
  // A rocket body struck by a spacecraft: each fragment follows its own parent's class.
  BreakupEvent event = breakup_test::reference_collision(11700.0, 0.05, 0);
  event.parents[1].object_class = BreakupObjectClass::kRocketBody;
  check_bands(pooled(event, 6), event, "spacecraft onto rocket body");
}

TEST(BreakupDistribution, EjectionDirectionIsIsotropic) {
  const FragmentCloud c = pooled(breakup_test::reference_collision(11700.0, 0.02, 0), 1);
  std::vector<double> cos_theta, phi;
  double mean[3] = {0, 0, 0};
  for (std::size_t i = 0; i < c.delta_v_m_s.x.size(); ++i) {
    const double x = c.delta_v_m_s.x[i], y = c.delta_v_m_s.y[i], z = c.delta_v_m_s.z[i];
    const double s = std::hypot(x, y, z);
    cos_theta.push_back(0.5 * (z / s + 1.0));
    phi.push_back((std::atan2(y, x) + M_PI) / (2.0 * M_PI));
    mean[0] += x / s, mean[1] += y / s, mean[2] += z / s;
  }
  const std::size_t n = cos_theta.size();
  std::printf("direction: n %zu, KS cos(theta) %.4f, phi %.4f (critical %.4f)\n", n, ks_uniform(cos_theta),
              ks_uniform(phi), ks_critical(n));
  EXPECT_LT(ks_uniform(cos_theta), ks_critical(n));
  EXPECT_LT(ks_uniform(phi), ks_critical(n));
  // The mean unit vector of n isotropic directions has a per-axis standard deviation sqrt(1 / (3 n)).
  for (double m : mean) EXPECT_LT(std::abs(m / static_cast<double>(n)), 4.0 * std::sqrt(1.0 / (3.0 * n)));
}

}  // namespace
}  // namespace kessler
