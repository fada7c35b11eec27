// Fragment counts of the three reference cases and the cumulative size distribution against the power
// law (tests/data/breakup/sbm_reference.json).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "core/breakup/energy_and_count.hpp"
#include "core/breakup/fragment_cloud.hpp"
#include "core/breakup/size_distribution.hpp"
#include "tests/breakup/reference.hpp"

namespace kessler {
namespace {

using breakup_test::reference_collision;
using breakup_test::reference_explosion;
using breakup_test::reference_number;

// Largest |count(size >= L) - expected(L)| over L = Lc_min * 1.005^k up to Lc_max, as a fraction of the
// count; expected(L) = count * P(size >= L) of the power law truncated to [Lc_min, Lc_max].
double max_cdf_deviation(const FragmentCloud& cloud, double lc_min, double lc_max, double exponent) {
  std::vector<double> sizes = cloud.characteristic_length_m;
  std::sort(sizes.begin(), sizes.end());
  const double n = static_cast<double>(cloud.drawn_count);
  const double lo = std::pow(lc_min, -exponent), hi = std::pow(lc_max, -exponent);
  double worst = 0.0;
  for (double lc = lc_min; lc <= lc_max; lc *= 1.005) {
    const auto at_least = static_cast<double>(sizes.end() - std::lower_bound(sizes.begin(), sizes.end(), lc));
    const double expected = n * (std::pow(lc, -exponent) - hi) / (lo - hi);
    worst = std::max(worst, std::abs(at_least - expected) / n);
  }
  return worst;
}

TEST(BreakupCount, CatastrophicCollisionMatchesReference) {
  const std::string test = "CollisionTest.FragmentCountTest";
  const BreakupEvent event = reference_collision(11700.0, reference_number(test, "Lc_min_m"), 1);
  const FragmentCloud cloud = generate_fragments(event);
  EXPECT_TRUE(cloud.catastrophic);
  EXPECT_NEAR(cloud.expected_count, reference_number(test, "formula_value"), 1e-6);
  EXPECT_EQ(cloud.drawn_count, static_cast<std::uint64_t>(reference_number(test, "expected_fragment_count")));
  // Mass conservation may drop a few of the heaviest: at most 0.5 % of the count.
  EXPECT_GE(static_cast<double>(cloud.size()), 0.995 * static_cast<double>(cloud.drawn_count));
  EXPECT_FALSE(cloud.remnant.has_value());
}

TEST(BreakupCount, NonCatastrophicCollisionMatchesReference) {
  const std::string test = "NonCatastrophicCollisionTest.FragmentCountTest";
  const BreakupEvent event = reference_collision(100.0, reference_number(test, "Lc_min_m"), 1);
  const FragmentCloud cloud = generate_fragments(event);
  EXPECT_FALSE(cloud.catastrophic);
  EXPECT_NEAR(cloud.specific_energy_j_per_g, reference_number(test, "E_p_J_per_g"), 1e-9);
  EXPECT_NEAR(cloud.expected_count, reference_number(test, "formula_value"), 1e-6);
  EXPECT_EQ(cloud.drawn_count, static_cast<std::uint64_t>(reference_number(test, "expected_fragment_count")));
  EXPECT_EQ(cloud.size(), cloud.drawn_count);
  ASSERT_TRUE(cloud.remnant.has_value());
  EXPECT_EQ(cloud.remnant->parent_id, 2251u);  // the 950 kg target survives
  EXPECT_NEAR(cloud.remnant->mass_kg + cloud.fragment_mass_kg, 1510.0, 1e-9);
}

TEST(BreakupCount, ExplosionMatchesReference) {
  const std::string test = "ExplosionTest.FragmentCountTest";
  const BreakupEvent event = reference_explosion(reference_number(test, "Lc_min_m"), 1);
  const FragmentCloud cloud = generate_fragments(event);
  EXPECT_NEAR(cloud.expected_count, reference_number(test, "formula_value"), 1e-6);
  EXPECT_EQ(cloud.drawn_count, static_cast<std::uint64_t>(reference_number(test, "expected_fragment_count")));
  EXPECT_GE(static_cast<double>(cloud.size()), 0.995 * static_cast<double>(cloud.drawn_count));
}

TEST(BreakupCount, CatastrophicThresholdIsFortyJoulesPerGram) {
  // 560 kg onto 950 kg: E_p = 40 J/g at v = sqrt(2 * 40e3 * 950 / 560) m/s.
  const double v40 = std::sqrt(2.0 * 40e3 * 950.0 / 560.0);
  EXPECT_TRUE(generate_fragments(reference_collision(v40 * 1.001, 0.5, 1)).catastrophic);
  EXPECT_FALSE(generate_fragments(reference_collision(v40 * 0.999, 0.5, 1)).catastrophic);
  EXPECT_NEAR(collision_mass_kg(false, 950.0, 560.0, 3000.0), 560.0 * 9.0, 1e-9);
  EXPECT_NEAR(collision_cumulative_count(1000.0, 1.0), 0.1 * std::pow(1000.0, 0.75), 1e-9);
  EXPECT_NEAR(explosion_cumulative_count(2.0, 0.1), 12.0 * std::pow(0.1, -1.6), 1e-9);
}

struct SizeCase {
  const char* name;
  const char* deviation_key;
  BreakupEvent event;
  double lc_max, exponent;
};

TEST(BreakupSize, CumulativeDistributionFollowsPowerLaw) {
  const std::vector<SizeCase> cases = {
      {"catastrophic", "catastrophic", reference_collision(11700.0, 0.05, 1), 2.0, 1.71},
      {"non-catastrophic", "non-catastrophic", reference_collision(100.0, 0.05, 1), 2.0, 1.71},
      {"explosion", "explosion", reference_explosion(0.05, 1), 3.6, 1.6},
  };
  for (const SizeCase& c : cases) {
    const double allowed = breakup_test::size_deviation_fraction(c.deviation_key);
    for (std::uint64_t id = 1; id <= 8; ++id) {
      BreakupEvent e = c.event;
      e.event_id = id;
      const FragmentCloud cloud = generate_fragments(e);
      const double dev = max_cdf_deviation(cloud, e.min_characteristic_length_m, c.lc_max, c.exponent);
      if (id == 1)
        std::printf("%s: max CDF deviation %.5f of %zu (allowed %.3f)\n", c.name, dev,
                    static_cast<std::size_t>(cloud.drawn_count), allowed);
      EXPECT_LE(dev, allowed) << c.name << " event " << id;
      for (double lc : cloud.characteristic_length_m) {
        ASSERT_GE(lc, e.min_characteristic_length_m);
        ASSERT_LE(lc, c.lc_max);
      }
    }
  }
}

TEST(BreakupSize, AreaFromCharacteristicLength) {
  const std::string json = breakup_test::reference_json();
  const std::size_t examples = json.find("\"area_examples_m2\"");
  ASSERT_NE(examples, std::string::npos);
  for (const char* lc : {"0.001", "0.01", "0.1", "1.0"}) {
    const std::size_t at = json.find(std::string("\"") + lc + "\":", examples);
    ASSERT_NE(at, std::string::npos) << lc;
    const double area = std::stod(json.substr(json.find(':', at) + 1));
    EXPECT_NEAR(area_from_size(std::stod(lc)) / area, 1.0, 1e-12) << lc;
  }
}

}  // namespace
}  // namespace kessler
