// Launch plans: the objects of a plan appear where the plan puts them (altitude, inclination, planes,
// epochs), read back from the states by geometry of their own, not by the code that placed them; bad
// plans are refused with the line and the column.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <map>
#include <numbers>
#include <set>
#include <sstream>

#include <Eigen/Geometry>

#include "core/catalog/object_properties.hpp"
#include "core/catalog/satcat.hpp"
#include "core/catalog/tle.hpp"
#include "core/physics/atmosphere.hpp"
#include "core/physics/constants.hpp"
#include "core/traffic/business_as_usual.hpp"
#include "core/traffic/launch_plan.hpp"
#include "core/traffic/lifecycle.hpp"

namespace kessler {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

std::string read(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// Inclination and RAAN [deg] from a state: the angular momentum's tilt and its node's direction.
void plane_of(const Eigen::Vector3d& r, const Eigen::Vector3d& v, double& inclination_deg, double& raan_deg) {
  const Eigen::Vector3d h = r.cross(v);
  inclination_deg = std::acos(h.z() / h.norm()) / kDeg;
  raan_deg = std::atan2(h.x(), -h.y()) / kDeg;
  if (raan_deg < 0.0) raan_deg += 360.0;
}

TEST(OrbitElements, StatesHaveTheElementsGeometry) {
  OrbitElements el = elements_from_altitudes(500e3, 1500e3, 63.4 * kDeg);
  el.raan_rad = 1.0;
  el.argument_of_perigee_rad = 2.0;
  const double mu = constants::kEarthMu_m3_s2, a = el.semi_major_axis_m;
  for (double m : {0.0, 0.7, 3.14159, 5.0}) {
    el.mean_anomaly_rad = m;
    Eigen::Vector3d r, v;
    state_from_elements(el, r, v);
    EXPECT_NEAR(v.squaredNorm() / 2.0 - mu / r.norm(), -mu / (2.0 * a), 1e-6 * mu / a);  // vis-viva
    double inc = 0.0, raan = 0.0;
    plane_of(r, v, inc, raan);
    EXPECT_NEAR(inc, 63.4, 1e-9);
    EXPECT_NEAR(raan, 1.0 / kDeg, 1e-9);
    // Perigee and apogee from the eccentricity vector and a.
    const Eigen::Vector3d e_vec = v.cross(r.cross(v)) / mu - r.normalized();
    EXPECT_NEAR(a * (1.0 - e_vec.norm()) - constants::kEarthEquatorialRadius_m, 500e3, 1e-3);
  }
  const double e = 0.3, ea = eccentric_anomaly(2.5, e);
  EXPECT_NEAR(ea - e * std::sin(ea), 2.5, 1e-14);
}

TEST(LaunchPlan, StarlinkShellsAppearInTheirPlanesAtTheirAltitudes) {
  const LaunchPlan plan = parse_launch_plan_csv(read(KESSLER_SOURCE_DIR "/deploy/traffic/starlink-gen1.csv"));
  ASSERT_EQ(plan.rows.size(), 5u);
  const UtcEpoch start = UtcEpoch::from_calendar(2022, 1, 1, 0, 0, 0.0);
  const auto objects = expand_launch_plan(plan, start, 3.0 * 365.25 * 86400.0, 1);
  ASSERT_EQ(objects.size(), 4408u);
  // Shell 1: 72 planes 5 deg apart, 22 satellites each, 53.0 deg, circular at 550 km, launched within
  // 2022-01-01 .. 2023-12-31.
  std::map<long, int> per_plane;
  const double end_s = UtcEpoch::from_calendar(2023, 12, 31, 0, 0, 0.0).seconds_since(start);
  double last_t = -1.0;
  for (const PlannedObject& o : objects) {
    EXPECT_GE(o.epoch_offset_s, last_t);  // in epoch order
    last_t = o.epoch_offset_s;
    if (o.row != 0) continue;
    Eigen::Vector3d r, v;
    state_from_elements(o.elements, r, v);
    double inc = 0.0, raan = 0.0;
    plane_of(r, v, inc, raan);
    EXPECT_NEAR(inc, 53.0, 1e-9);
    EXPECT_NEAR(r.norm() - constants::kEarthEquatorialRadius_m, 550e3, 1e-3);
    EXPECT_NEAR(r.dot(v), 0.0, 1e-3 * r.norm());  // circular: no radial speed
    EXPECT_GE(o.epoch_offset_s, 0.0);
    EXPECT_LE(o.epoch_offset_s, end_s + 1e-6);
    EXPECT_NEAR(raan / 5.0, std::round(raan / 5.0), 1e-6);
    ++per_plane[std::lround(raan / 5.0) % 72];
    EXPECT_EQ(o.type, ObjectType::kPayload);
    EXPECT_NEAR(o.lifetime_s, 5.0 * 365.25 * 86400.0, 1e-6);
  }
  EXPECT_EQ(per_plane.size(), 72u);
  for (const auto& [plane, n] : per_plane) EXPECT_EQ(n, 22) << plane;
}

TEST(LaunchPlan, OnlyTheLaunchesInsideTheRunAreMade) {
  const LaunchPlan plan = parse_launch_plan_csv(
      "epoch,count,altitude_km,inclination_deg\n"
      "2021-06-01T00:00:00Z,3,500,10\n"
      "2022-02-01T00:00:00Z,4,700,20\n"
      "2030-01-01T00:00:00Z,5,800,30\n");
  const auto objects =
      expand_launch_plan(plan, UtcEpoch::from_calendar(2022, 1, 1, 0, 0, 0.0), 86400.0 * 365, 1);
  ASSERT_EQ(objects.size(), 4u);
  for (const PlannedObject& o : objects) EXPECT_EQ(o.row, 1u);
}

void expect_refused(const std::string& csv, std::size_t line, const std::string& column) {
  try {
    parse_launch_plan_csv(csv);
    ADD_FAILURE() << "accepted: " << csv;
  } catch (const LaunchPlanError& e) {
    EXPECT_EQ(e.line(), line) << e.what();
    EXPECT_EQ(e.column(), column) << e.what();
  }
}

TEST(LaunchPlan, BadPlansAreRefusedWithTheLineAndColumn) {
  const std::string head = "epoch,count,altitude_km,inclination_deg\n";
  expect_refused("epoch,count,altitude_km,inclination_deg,Colour\n2022-01-01T00:00:00Z,1,500,10,red\n", 1,
                 "colour");
  expect_refused(head + "2022-01-01T00:00:00Z,-2,500,10\n", 2, "count");
  expect_refused(head + "2022-01-01T00:00:00Z,0,500,10\n", 2, "count");
  expect_refused(head + "2022-01-01T00:00:00Z,1,500,10\nyesterday,1,500,10\n", 3, "epoch");
  expect_refused(head + "2022-01-01T00:00:00Z,1,90,10\n", 2, "altitude_km");
  expect_refused(head + "2022-01-01T00:00:00Z,1,50000,10\n", 2, "altitude_km");
  expect_refused(head + "2022-01-01T00:00:00Z,1,500,190\n", 2, "inclination_deg");
  expect_refused(head + "2022-01-01T00:00:00Z,1,abc,10\n", 2, "altitude_km");
  expect_refused("epoch,count,altitude_km,inclination_deg,planes\n2022-01-01T00:00:00Z,10,500,10,3\n", 2,
                 "planes");
  expect_refused("epoch,count,perigee_km,apogee_km,inclination_deg\n2022-01-01T00:00:00Z,1,800,500,10\n", 2,
                 "perigee_km");
  expect_refused("epoch,count,altitude_km,inclination_deg,type\n2022-01-01T00:00:00Z,1,500,10,station\n", 2,
                 "type");
}

// The 2022 catalog's objects launched 2013-2020 (SATCAT launch dates), relaunched 8 years later: each
// row is a record of the window on its own orbit, exactly one cycle after its launch date. Objects that
// decayed before the catalog are relaunched too, passive, on a circular orbit that decays in the time they
// lived, in the plane of their launch's first object in LEO.
TEST(BusinessAsUsual, RepeatsTheWindowsLaunchesOneCycleLater) {
  std::string error;
  const auto satcat = read_catalog_file(
      KESSLER_SOURCE_DIR "/deploy/datasets/catalog/spacetrack_satcat_2021-01-19.csv.gz", &error);
  ASSERT_TRUE(satcat) << error;
  const auto tles = read_catalog_file(
      KESSLER_SOURCE_DIR "/deploy/datasets/catalog/spacetrack_3le_2022-01-22_ODAP.txt", &error);
  ASSERT_TRUE(tles) << error;
  std::vector<MeanElements> sets;
  for (const ElementSetEntry& e : parse_tle_text(*tles, {}, "3le").sets) sets.push_back(e.elements);
  const std::vector<LaunchRecord> records = launch_records(*satcat, sets);
  ASSERT_GT(records.size(), 5000u);
  const UtcEpoch window_end = UtcEpoch::from_calendar(2021, 1, 1, 0, 0, 0.0);
  const UtcEpoch until = UtcEpoch::from_calendar(2029, 1, 1, 0, 0, 0.0);
  const LaunchPlan plan = business_as_usual_plan(records, window_end, 8.0, until);
  std::size_t in_window = 0, decayed = 0;
  for (const LaunchRecord& r : records) {
    const double age = window_end.seconds_since(r.launch);
    if (!(age > 0.0 && age <= 8.0 * 365.25 * 86400.0)) continue;
    decayed += r.lived_years > 0.0;
    in_window +=
        r.lived_years > 0.0 || (r.perigee_km < 2000.0 && r.perigee_km >= 100.0 && r.apogee_km <= 40000.0);
  }
  ASSERT_GT(in_window, 1000u);  // Starlink alone launched about a thousand in 2019-2020
  // Counted from the two files on their own: payloads and rocket bodies launched 2013-2020 with no
  // element set in 2022, a SATCAT decay date after their launch date, and an object of their launch
  // (INTLDES year-number) in the 2022 catalog with a perigee below 2,000 km.
  EXPECT_EQ(decayed, 210u);
  EXPECT_EQ(plan.rows.size(), in_window);  // one cycle in 8 years: each once
  std::map<std::string, const LaunchRecord*> by_label;
  for (const LaunchRecord& r : records) by_label["business as usual: " + std::to_string(r.id)] = &r;
  for (const LaunchRow& row : plan.rows) {
    const LaunchRecord& r = *by_label.at(row.label);
    EXPECT_NEAR(row.epoch.seconds_since(r.launch), 8.0 * 365.25 * 86400.0, 1e-3);
    EXPECT_EQ(row.inclination_deg, r.inclination_deg);
    EXPECT_EQ(row.type, r.type);
    if (r.lived_years > 0.0) {
      EXPECT_EQ(row.perigee_km, row.apogee_km);
      EXPECT_EQ(row.lifetime_years, 0.0);  // passive from launch
      EXPECT_FALSE(row.manoeuvres);
    } else {
      EXPECT_EQ(row.perigee_km, r.perigee_km);
    }
  }
  // Three rocket bodies of 2019 that decayed within weeks, and their launches' planes in the 2022
  // catalog: CZ-11 (SATCAT 43945, 7 days, 97.5157 deg), Antares (44206, 11 days, 51.6399 deg), Electron
  // (44228, 12 days, 40.0161 deg).
  const std::map<ObjectId, std::pair<double, double>> expected = {
      {43945, {7.0, 97.5157}}, {44206, {11.0, 51.6399}}, {44228, {12.0, 40.0161}}};
  std::size_t found = 0;
  for (const LaunchRecord& r : records) {
    auto it = expected.find(r.id);
    if (it == expected.end()) continue;
    ++found;
    EXPECT_NEAR(r.lived_years * 365.25, it->second.first, 1e-9) << r.id;
    EXPECT_NEAR(r.inclination_deg, it->second.second, 1e-3) << r.id;
  }
  EXPECT_EQ(found, 3u);
}

// A decayed object's relaunch orbit decays, in the model that sets disposal orbits, in the time it lived.
TEST(BusinessAsUsual, ADecayedObjectsOrbitDecaysInTheTimeItLived) {
  const double inclination = 51.6;
  for (double years : {0.05, 0.5, 2.0, 6.0}) {
    for (ObjectType type : {ObjectType::kPayload, ObjectType::kRocketBody}) {
      const double h_km = altitude_for_lifetime_km(years, inclination, type);
      const bool payload = type == ObjectType::kPayload;
      const double cda = drag_area_to_mass_from_size(payload ? 1.5 : 2.0, payload ? 260.0 : 1500.0, 2.2);
      const double lived = circular_decay_years(h_km * 1e3, inclination * std::numbers::pi / 180.0, cda,
                                                150.0e3, DensityTable::standard());
      EXPECT_GT(h_km, 160.0);
      EXPECT_LT(h_km, 700.0);
      EXPECT_NEAR(lived, years, 0.03 * years) << years << " years, " << h_km << " km";
    }
  }
  // Longer lives need higher orbits.
  EXPECT_LT(altitude_for_lifetime_km(0.5, inclination, ObjectType::kPayload),
            altitude_for_lifetime_km(2.0, inclination, ObjectType::kPayload));
}

}  // namespace
}  // namespace kessler
