// Post-mission disposal: the success draws match their probability, and a disposed object re-enters
// within its target lifetime when the project's own propagator carries it (drag in the default table
// atmosphere).
#include <gtest/gtest.h>

#include <cmath>

#include "core/integration/symplectic_propagator.hpp"
#include "core/physics/atmosphere.hpp"
#include "core/physics/constants.hpp"
#include "core/traffic/lifecycle.hpp"

namespace kessler {
namespace {

constexpr double kYear_s = 365.25 * 86400.0;

TEST(Disposal, SuccessesMatchTheProbabilityWithinSamplingError) {
  constexpr int kObjects = 200000;
  for (double p : {0.9, 0.5, 0.99}) {
    int ok = 0;
    for (int id = 0; id < kObjects; ++id) ok += disposal_succeeds(42, static_cast<ObjectId>(id), p);
    const double sigma = std::sqrt(p * (1.0 - p) / kObjects);
    EXPECT_NEAR(static_cast<double>(ok) / kObjects, p, 4.0 * sigma) << p;
  }
  // Keyed by the object: the same answer every time, and a different seed draws anew.
  EXPECT_EQ(disposal_succeeds(42, 7, 0.5), disposal_succeeds(42, 7, 0.5));
  int same = 0;
  for (int id = 0; id < 1000; ++id) same += disposal_succeeds(1, id, 0.5) == disposal_succeeds(2, id, 0.5);
  EXPECT_NEAR(same, 500, 80);
}

TEST(Disposal, TheDisposalAltitudeGivesTheTargetLifetime) {
  const DensityTable& table = DensityTable::standard();
  const double drag = 2.2 * 0.01;  // Cd A/m of a typical payload
  double last = 0.0;
  for (double years : {1.0, 5.0, 25.0}) {
    const double h = disposal_altitude_m(years, 0.9, drag, 150e3, 2000e3, table);
    EXPECT_GT(h, last);  // a longer life, a higher orbit
    last = h;
    EXPECT_NEAR(circular_decay_years(h, 0.9, drag, 150e3, table), years, 0.02 * years);
  }
  // Never raised: an object already lower than the disposal altitude stays put.
  EXPECT_EQ(disposal_altitude_m(25.0, 0.9, drag, 150e3, 400e3, table), 400e3);
}

TEST(Disposal, ADisposedObjectReentersWithinItsTargetLifetime) {
  // A 40-day target for a high area-to-mass object, so the check runs in a fraction of a second: the
  // propagator (Kepler and drag, the table) takes it from the disposal orbit (45 deg) to the burn-up
  // altitude.
  const DensityTable& table = DensityTable::standard();
  const double drag = 2.2 * 0.05, target_years = 40.0 / 365.25;
  const double h = disposal_altitude_m(target_years, std::acos(std::sqrt(0.5)), drag, 150e3, 1000e3, table);
  Eigen::Vector3d r(constants::kEarthEquatorialRadius_m + 800e3, 0.0, 0.0), v(0.0, 5000.0, 5000.0);
  move_to_circular_orbit(constants::kEarthEquatorialRadius_m + h, r, v);
  EXPECT_NEAR(r.norm() - constants::kEarthEquatorialRadius_m, h, 1e-6);
  EXPECT_NEAR(v.norm(), std::sqrt(constants::kEarthMu_m3_s2 / r.norm()), 1e-9);
  EXPECT_NEAR(r.dot(v), 0.0, 1e-3);
  ForceModelSettings forces{true, false, false, true, false, false};
  SymplecticPropagator propagator(forces, UtcEpoch::from_calendar(2022, 1, 1, 0, 0, 0.0),
                                  Integrator::kBlanesMoan4);
  Population p;
  ObjectRecord o;
  o.id = 1;
  o.position_m = r;
  o.velocity_m_s = v;
  o.radius_m = 1.0;
  o.mass_kg = 100.0;
  o.drag_area_to_mass_m2_kg = drag;
  p.add(o);
  double t = 0.0;
  const double dt = 30.0;
  while (p.state.position(0).norm() - constants::kEarthEquatorialRadius_m > 150e3 &&
         t < 2.0 * target_years * kYear_s) {
    propagator.step(p, t, dt);
    t += dt;
  }
  std::printf("disposal at %.1f km: re-entry after %.2f days (target %.2f)\n", h / 1e3, t / 86400.0,
              target_years * 365.25);
  EXPECT_NEAR(t / kYear_s, target_years, 0.03 * target_years);
}

}  // namespace
}  // namespace kessler
