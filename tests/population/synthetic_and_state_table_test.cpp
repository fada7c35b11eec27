// The synthetic generator's distributions against the catalog histograms it encodes, its determinism,
// and the state-vector table reader.
#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>

#include "core/catalog/state_table.hpp"
#include "core/catalog/synthetic.hpp"
#include "core/physics/constants.hpp"

namespace kessler {
namespace {

TEST(Synthetic, DistributionsAndBand) {
  SyntheticOptions o;
  o.objects = 100000;
  const Population p = generate_synthetic(o, 5);
  ASSERT_EQ(p.size(), 100000u);
  EXPECT_FALSE(p.validate().has_value());
  std::size_t active = 0, below_600 = 0;
  const double mu = constants::kEarthMu_m3_s2, re = constants::kEarthEquatorialRadius_m;
  for (std::size_t i = 0; i < p.size(); ++i) {
    active += p.status[i] == ObjectStatus::kActive;
    // Semi-major axis from the vis-viva equation: inside the band.
    const double r = p.state.position(i).norm(), v2 = p.state.velocity(i).squaredNorm();
    const double a = 1.0 / (2.0 / r - v2 / mu);
    ASSERT_GE(a - re, 300e3 - 1.0);
    ASSERT_LE(a - re, 1500e3 + 1.0);
    ASSERT_GE(r - re, 300e3 - 1.0);  // perigee cap keeps every point above the band's lower edge
    below_600 += a - re < 600e3;
  }
  // Active fraction 0.125: binomial standard deviation ~0.001.
  EXPECT_NEAR(active / 1e5, 0.125, 0.005);
  // Catalog histogram (synthetic.cpp): bins 300..600 km hold 247 + 1522 + 1795 = 3564 of the 16,139
  // catalog objects with semi-major-axis altitudes in 300..1500 km -> 0.2208 (sd of the estimate 0.0013).
  EXPECT_NEAR(below_600 / 1e5, 3564.0 / 16139.0, 0.005);
}

TEST(Synthetic, SameForAnyThreadCountAndSeedDependent) {
  SyntheticOptions o;
  o.objects = 5000;
  omp_set_num_threads(1);
  const Population a = generate_synthetic(o, 9);
  omp_set_num_threads(4);
  const Population b = generate_synthetic(o, 9);
  const Population c = generate_synthetic(o, 10);
  EXPECT_EQ(a.state.x, b.state.x);
  EXPECT_EQ(a.radius_m, b.radius_m);
  EXPECT_NE(a.state.x, c.state.x);
  o.min_altitude_km = 900;
  o.max_altitude_km = 800;
  EXPECT_THROW(generate_synthetic(o, 1), std::invalid_argument);
}

TEST(StateTable, RowsAndBadRows) {
  const UtcEpoch start = UtcEpoch::from_calendar(2022, 1, 1, 0, 0, 0);
  const std::string text =
      "id,epoch,x,y,z,vx,vy,vz,radius,mass,bstar\n"
      "1,2022-01-01T00:00:00Z,7000000,0,0,0,7546,0,0.5,,\n"
      "2,2022-01-01T00:00:00Z,0,7000000,0,-7546,0,0,0.1,3.5,0.0001\n"
      "3,2022-01-02T00:00:00Z,0,7000000,0,-7546,0,0,0.1,3.5,0.0001\n"
      "4,2022-01-01T00:00:00Z,0,70x0000,0,-7546,0,0,0.1,3.5,0.0001\n"
      "5,2022-01-01T00:00:00Z,0,7000000,0,-7546,0,0,0.1\n";
  const IngestResult r = read_state_table(text, IngestRules{}, start, "states.csv");
  ASSERT_EQ(r.population.size(), 2u);
  EXPECT_NEAR(r.population.mass_kg[0], mass_from_radius_kg(0.5), 1e-12);
  EXPECT_NEAR(r.population.drag_area_to_mass_m2_kg[1], 2e-4 / 0.15696615, 1e-15);
  EXPECT_NEAR(r.population.drag_area_to_mass_m2_kg[0],
              2.2 * 3.14159265358979 * 0.25 / mass_from_radius_kg(0.5), 1e-9);
  ASSERT_EQ(r.report.rejections.size(), 3u);
  EXPECT_EQ(r.report.rejections[0].line, 4u);
  EXPECT_EQ(r.report.rejections[0].reason_key, "epoch");
  EXPECT_EQ(r.report.rejections[1].line, 5u);
  EXPECT_NE(r.report.rejections[1].message.find("y:"), std::string::npos) << r.report.rejections[1].message;
  EXPECT_EQ(r.report.rejections[2].reason_key, "columns");
  IngestRules strict;
  strict.strict = true;
  const IngestResult refused = read_state_table(text, strict, start, "states.csv");
  EXPECT_TRUE(refused.refused);
  EXPECT_NE(refused.error.find("line 4"), std::string::npos) << refused.error;
}

}  // namespace
}  // namespace kessler
