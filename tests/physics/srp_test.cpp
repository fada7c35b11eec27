// Solar radiation pressure and the Sun ephemeris against published figures.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include <Eigen/Geometry>

#include "core/physics/force_model.hpp"
#include "core/physics/sun_ephemeris.hpp"

namespace kessler {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;
constexpr double kAu = constants::kAstronomicalUnit_m;

TEST(Srp, MagnitudeAtOneAuIsPressureTimesAreaToMassAwayFromTheSun) {
  // Sun placed so the object is exactly 1 AU from it, on the lit side.
  const Eigen::Vector3d r(7000e3, 0, 0);
  SunGeometry sun{7000e3 + kAu, 0, 0, 1, 0, 0, 6378137.0 * 6378137.0};
  double ax, ay, az;
  srp_acceleration(4.56e-6 * kAu * kAu, sun, 0.02, r.x(), r.y(), r.z(), ax, ay, az);
  EXPECT_NEAR(ax, -4.56e-6 * 0.02, 1e-15 * 4.56e-6 * 0.02);
  EXPECT_EQ(ay, 0.0);
  EXPECT_EQ(az, 0.0);
}

TEST(Srp, ScalesWithInverseSquareDistanceInTheForceModel) {
  ForceModelSettings srp_only;
  srp_only.kepler = srp_only.j2 = srp_only.c22_s22 = srp_only.drag = false;
  const UtcEpoch epoch = UtcEpoch::from_calendar(2022, 3, 1, 0, 0, 0);
  ForceModel model(srp_only, epoch);
  const Eigen::Vector3d sun = sun_position_m(epoch);
  const Eigen::Vector3d r = 7000e3 * sun.normalized().cross(Eigen::Vector3d::UnitZ()).normalized();  // lit
  const Eigen::Vector3d a = model.acceleration(r, Eigen::Vector3d::Zero(), 0.0, {0.0, 0.01});
  const double d = (r - sun).norm();
  EXPECT_NEAR(a.norm(), 4.56e-6 * 0.01 * (kAu / d) * (kAu / d), 1e-13 * a.norm());
  EXPECT_GT(a.dot(r - sun), 0.0);
}

TEST(Srp, ZeroInTheEarthsCylindricalShadow) {
  ForceModelSettings srp_only;
  srp_only.kepler = srp_only.j2 = srp_only.c22_s22 = srp_only.drag = false;
  const UtcEpoch epoch = UtcEpoch::from_calendar(2022, 6, 21, 12, 0, 0);
  ForceModel model(srp_only, epoch);
  const Eigen::Vector3d toward_sun = sun_position_m(epoch).normalized();
  const Eigen::Vector3d side = toward_sun.cross(Eigen::Vector3d::UnitZ()).normalized();
  auto srp = [&](const Eigen::Vector3d& r) {
    return model.acceleration(r, Eigen::Vector3d::Zero(), 0.0, {0.0, 0.01}).norm();
  };
  EXPECT_EQ(srp(-7000e3 * toward_sun), 0.0);                     // straight behind the Earth
  EXPECT_EQ(srp(-7000e3 * toward_sun + 6300e3 * side), 0.0);     // inside the cylinder's edge
  EXPECT_GT(srp(-7000e3 * toward_sun + 6400e3 * side), 4.0e-8);  // just outside it
  EXPECT_GT(srp(7000e3 * toward_sun), 4.0e-8);                   // day side
  srp_only.srp_earth_shadow = false;                             // the paper's model: no shadow
  ForceModel no_shadow(srp_only, epoch);
  EXPECT_GT(no_shadow.acceleration(-7000e3 * toward_sun, Eigen::Vector3d::Zero(), 0.0, {0.0, 0.01}).norm(),
            4e-8);
}

double right_ascension_deg(const Eigen::Vector3d& s) {
  double ra = std::atan2(s.y(), s.x()) / kDeg;
  return ra < 0 ? ra + 360 : ra;
}
double declination_deg(const Eigen::Vector3d& s) {
  return std::asin(s.z() / s.norm()) / kDeg;
}

TEST(SunEphemeris, EquinoxSolsticeAndPerihelionOf2022) {
  // March equinox 2022-03-20 15:33 UTC: the Sun crosses the equator at RA 0.
  const Eigen::Vector3d equinox = sun_position_m(UtcEpoch::from_calendar(2022, 3, 20, 15, 33, 0));
  EXPECT_NEAR(declination_deg(equinox), 0.0, 0.01);
  EXPECT_NEAR(std::remainder(right_ascension_deg(equinox), 360.0), 0.0, 0.01);
  // June solstice 2022-06-21 09:14 UTC: RA 90 deg, declination = obliquity 23.436 deg.
  const Eigen::Vector3d solstice = sun_position_m(UtcEpoch::from_calendar(2022, 6, 21, 9, 14, 0));
  EXPECT_NEAR(right_ascension_deg(solstice), 90.0, 0.01);
  EXPECT_NEAR(declination_deg(solstice), 23.436, 0.01);
  // Perihelion 2022-01-04 06:55 UTC at 0.983336 AU; aphelion 2022-07-04 07:11 UTC at 1.016715 AU.
  EXPECT_NEAR(sun_position_m(UtcEpoch::from_calendar(2022, 1, 4, 6, 55, 0)).norm() / kAu, 0.983336, 1e-4);
  EXPECT_NEAR(sun_position_m(UtcEpoch::from_calendar(2022, 7, 4, 7, 11, 0)).norm() / kAu, 1.016715, 1e-4);
}

}  // namespace
}  // namespace kessler
