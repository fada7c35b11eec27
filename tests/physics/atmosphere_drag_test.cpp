// Density models against their published tables and formulas; drag against a hand computation and the
// expected orbital behaviour (decay, re-entry, dependence on the ballistic coefficient).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "core/integration/burn_up.hpp"
#include "core/integration/symplectic_propagator.hpp"
#include "core/physics/atmosphere.hpp"
#include "core/physics/deterministic_exp.hpp"
#include "tests/physics/two_body.hpp"

namespace kessler {
namespace {

constexpr double kRe = constants::kEarthEquatorialRadius_m;

TEST(DeterministicExp, AgreesWithLibmToTwoUlp) {
  for (double x = -700.0; x <= 700.0; x += 0.0137) {
    const double expected = std::exp(x);
    EXPECT_NEAR(deterministic_exp(x), expected, 4.5e-16 * expected) << x;
  }
  EXPECT_EQ(deterministic_exp(0.0), 1.0);
}

TEST(DensityTable, EqualsVallado84AtEveryNode) {
  for (const auto& node : DensityTable::nodes())
    EXPECT_NEAR(DensityTable::standard().density_kg_m3(node.altitude_km * 1000.0), node.density_kg_m3,
                1e-14 * node.density_kg_m3)
        << node.altitude_km << " km";
}

TEST(DensityTable, PositiveAndDecreasingFrom150To2500Km) {
  const auto& table = DensityTable::standard();
  double previous = table.density_kg_m3(150e3);
  for (double h = 150e3 + 100.0; h <= 2500e3; h += 100.0) {
    const double rho = table.density_kg_m3(h);
    ASSERT_GT(rho, 0.0) << h;
    ASSERT_LT(rho, previous) << h;
    previous = rho;
  }
  // Above the table: the 268 km scale height of its last band (Vallado Table 8-4).
  EXPECT_NEAR(table.density_kg_m3(2000e3), 3.019e-15 * std::exp(-1000.0 / 268.0), 1e-12 * 3.019e-15);
  // Between nodes: exponential interpolation, e.g. 425 km is the geometric mean of 400 and 450 km.
  EXPECT_NEAR(table.density_kg_m3(425e3), std::sqrt(3.725e-12 * 1.585e-12), 1e-12 * 3e-12);
}

TEST(ExponentialFit, EqualsTheDatasetFormula) {
  // rho(h) = sum a_i exp(-(h - c_i) b_i) with the file's numbers (b in 1/km, c in km, h in km).
  const double a[] = {1.017099350971841922e-06, 7.864433749696440046e-01, 7.503418833901893756e-09,
                      8.639342521502260029e-14};
  const double b[] = {4.638229098022707969e-02, 1.860800478627226973e-01, 2.486671755963201086e-02,
                      4.810808523935952534e-03};
  const double c[] = {5.015945159890937255e+00, 2.284298087732807758e+01, 4.279578287441034412e+00,
                      1.562916727761204660e-01};
  for (double h_km : {150.0, 300.0, 400.0, 550.0, 800.0, 1200.0, 2000.0}) {
    double expected = 0;
    for (int i = 0; i < 4; ++i) expected += a[i] * std::exp(-(h_km - c[i]) * b[i]);
    EXPECT_NEAR(exponential_fit_density_kg_m3(h_km * 1000.0), expected, 1e-13 * expected) << h_km;
  }
  // Positive and decreasing over LEO.
  double previous = exponential_fit_density_kg_m3(150e3);
  for (double h = 150e3 + 500.0; h <= 2500e3; h += 500.0) {
    const double rho = exponential_fit_density_kg_m3(h);
    ASSERT_GT(rho, 0.0) << h;
    ASSERT_LT(rho, previous) << h;
    previous = rho;
  }
}

ForceModelSettings drag_only(AtmosphereModel model = AtmosphereModel::kDensityTable) {
  ForceModelSettings s;
  s.kepler = s.j2 = s.c22_s22 = s.srp = false;
  s.atmosphere = model;
  return s;
}

const UtcEpoch kEpoch = UtcEpoch::from_calendar(2022, 3, 1, 0, 0, 0);

TEST(Drag, MatchesAHandComputationAt400Km) {
  // Object at 400 km on the x axis moving along +y at 7668.56 m/s with Cd A/m = 0.022 m^2/kg.
  // v_rel = v - omega x r = (0, 7668.56 - 7.292115146706979e-5 * 6778137, 0) = (0, 7174.29045, 0);
  // rho(400 km) = 3.725e-12 kg/m^3 (Vallado Table 8-4);
  // a_y = -1/2 * 3.725e-12 * 0.022 * 7174.29045^2 = -2.109001e-6 m/s^2.
  ForceModel model(drag_only(), kEpoch);
  const Eigen::Vector3d r(kRe + 400e3, 0, 0), v(0, 7668.56, 0);
  const Eigen::Vector3d a = model.acceleration(r, v, 0.0, {0.022, 0.0});
  const double v_rel = 7668.56 - 7.292115146706979e-5 * 6778137.0;
  const double expected = -0.5 * 3.725e-12 * 0.022 * v_rel * v_rel;
  EXPECT_NEAR(v_rel, 7174.29045, 1e-5);
  EXPECT_NEAR(expected, -2.109001e-6, 1e-12);
  EXPECT_NEAR(a.y(), expected, 1e-12 * std::abs(expected));
  EXPECT_EQ(a.x(), 0.0);
  EXPECT_EQ(a.z(), 0.0);
  // Out-of-plane velocity: the co-rotation only touches x and y.
  const Eigen::Vector3d v2(100.0, 7000.0, 2000.0);
  const Eigen::Vector3d rel(100.0, 7000.0 - 7.292115146706979e-5 * 6778137.0, 2000.0);
  const Eigen::Vector3d a2 = model.acceleration(r, v2, 0.0, {0.022, 0.0});
  EXPECT_LT((a2 - (-0.5 * 3.725e-12 * 0.022 * rel.norm() * rel)).norm(), 1e-12 * a2.norm());
  // With the dataset's fit instead of the table.
  ForceModel fit(drag_only(AtmosphereModel::kExponentialFit), kEpoch);
  const double rho_fit = exponential_fit_density_kg_m3(400e3);
  EXPECT_NEAR(fit.acceleration(r, v, 0.0, {0.022, 0.0}).y(), -0.5 * rho_fit * 0.022 * v_rel * v_rel,
              1e-12 * rho_fit * v_rel * v_rel);
}

Population circular(double altitude_m, const std::vector<double>& drag_area_to_mass) {
  Population p;
  for (std::size_t i = 0; i < drag_area_to_mass.size(); ++i) {
    ObjectRecord rec;
    rec.id = i + 1;
    testing::state_from_elements(kRe + altitude_m, 0.0, 51.6 * std::numbers::pi / 180, 0, 0, 0,
                                 rec.position_m, rec.velocity_m_s);
    rec.radius_m = 0.1;
    rec.mass_kg = 1;
    rec.drag_area_to_mass_m2_kg = drag_area_to_mass[i];
    rec.srp_area_to_mass_m2_kg = 0.01;
    p.add(rec);
  }
  return p;
}

TEST(Drag, CircularOrbitAt300KmDecaysEveryDayAndReEnters) {
  ForceModelSettings full;  // every term, density table
  SymplecticPropagator propagator(full, kEpoch);
  Population p = circular(300e3, {0.05});
  const double dt = 10.0;
  const long steps_per_day = 8640;
  double previous_mean = 300e3 + 1e9;
  std::vector<char> flags;
  int day = 0;
  bool reentered = false;
  for (; day < 60 && !reentered; ++day) {
    double sum = 0;
    long count = 0;
    for (long s = 0; s < steps_per_day; ++s) {
      const double t = (day * steps_per_day + s) * dt;
      propagator.step(p, t, dt);
      if (!find_burn_ups(p, 150e3, t + dt, flags).empty()) {
        reentered = true;
        break;
      }
      sum += p.state.position(0).norm() - kRe;
      ++count;
    }
    const double mean = sum / count;
    if (!reentered || count > steps_per_day / 2) {
      EXPECT_LT(mean, previous_mean) << "day " << day;
      previous_mean = mean;
    }
  }
  std::printf("re-entered below 150 km during day %d\n", day);
  EXPECT_TRUE(reentered);
  EXPECT_GT(day, 3);  // a 300 km orbit with Cd A/m = 0.05 lasts days, not hours
}

TEST(Drag, HigherBallisticCoefficientDecaysFaster) {
  ForceModelSettings full;
  SymplecticPropagator propagator(full, kEpoch);
  // Cd A/m = 2 B* / rho0: B* = 1e-4 and 5e-4 per Earth radius; a drag-free twin shares every other
  // perturbation, so semi-major axis differences to it isolate drag.
  const double low = 2 * 1e-4 / constants::kBstarRho0_kg_m2_per_er;
  Population p = circular(400e3, {0.0, low, 5 * low});
  const double dt = 10.0;
  for (long s = 0; s < 3 * 8640; ++s) propagator.step(p, s * dt, dt);
  // Orbit-averaged loss via the semi-major axis (vis-viva).
  auto sma = [&](std::size_t i) {
    return 1.0 / (2.0 / p.state.position(i).norm() - p.state.velocity(i).squaredNorm() / testing::kMu);
  };
  const double loss_low = sma(0) - sma(1), loss_high = sma(0) - sma(2);
  std::printf("3-day semi-major axis loss: low B* %.1f m, high B* %.1f m\n", loss_low, loss_high);
  // King-Hele's circular-orbit decay da/dt = -rho (Cd A/m) sqrt(mu a), with the co-rotating
  // atmosphere's factor (1 - omega a cos i / v)^2 on the relative speed squared.
  const double a0 = kRe + 400e3, v0 = std::sqrt(testing::kMu / a0);
  const double corotation = std::pow(
      1 - constants::kEarthRotationRate_rad_s * a0 * std::cos(51.6 * std::numbers::pi / 180) / v0, 2);
  const double king_hele = 3.725e-12 * low * std::sqrt(testing::kMu * a0) * 3 * 86400 * corotation;
  EXPECT_NEAR(loss_low, king_hele, 0.1 * king_hele);
  EXPECT_NEAR(loss_high / loss_low, 5.0, 0.25);
}

}  // namespace
}  // namespace kessler
