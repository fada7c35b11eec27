// The leo-19647 loader, refusal of bad input, and burn-up detection.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <numbers>

#include "core/catalog/leo19647.hpp"
#include "core/integration/burn_up.hpp"
#include "core/integration/symplectic_propagator.hpp"

namespace kessler {
namespace {

const std::string kDir = std::string(KESSLER_DATASETS_DIR) + "/leo-19647";

TEST(Leo19647, LoadsEveryObjectWithThePapersMassLaw) {
  const Population p = load_leo19647(kDir);
  ASSERT_EQ(p.size(), kLeo19647Objects);
  EXPECT_EQ(p.id.front(), 1u);
  EXPECT_EQ(p.id.back(), 19647u);
  EXPECT_FALSE(p.validate().has_value());
  // First object, from the file's first 7 lines and first drag parameter.
  EXPECT_EQ(p.state.x[0], 5.891186439331404865e+06);
  EXPECT_EQ(p.state.vz[0], -9.810447056225488041e+02);
  const double r = 1.970629496237749356e-01;
  EXPECT_EQ(p.radius_m[0], r);
  const double mass = 4.0 / 3.0 * std::numbers::pi * r * r * r * 92.937 * std::pow(2 * r, -0.74);
  EXPECT_NEAR(p.mass_kg[0], mass, 1e-12 * mass);
  EXPECT_NEAR(p.srp_area_to_mass_m2_kg[0], std::numbers::pi * r * r / mass, 1e-12);
  EXPECT_NEAR(p.drag_area_to_mass_m2_kg[0], 2 * 3.900512014715268781e-11 / (0.1570 / 6378137.0), 1e-15);
  EXPECT_EQ(leo19647_epoch().to_iso8601(0), "2022-03-01T00:00:00Z");
}

TEST(Leo19647, MassLawOfThePaper) {
  // r <= 1 cm: aluminium sphere; above: 92.937 (2r)^-0.74 kg/m^3 density law.
  EXPECT_NEAR(paper_mass_kg(0.005), 4.0 / 3.0 * std::numbers::pi * 1.25e-7 * 2698.9, 1e-15);
  EXPECT_NEAR(paper_mass_kg(0.5), 4.0 / 3.0 * std::numbers::pi * 0.125 * 92.937, 1e-12);  // (2r)^-0.74 = 1
  EXPECT_NEAR(paper_mass_kg(0.5), 48.6617, 1e-4);
}

class BadDataset : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() /
           ("kessler_leo_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  void write(const std::string& name, const std::string& text) { std::ofstream(dir_ / name) << text; }
  std::string error() {
    try {
      load_leo19647(dir_.string());
    } catch (const std::runtime_error& e) {
      return e.what();
    }
    return "";
  }
  std::filesystem::path dir_;
};

constexpr const char* kTwoObjects =
    "7000000\n0\n0\n0\n7500\n0\n0.5\n"
    "0\n7100000\n0\n-7400\n0\n0\n0.05\n";

TEST_F(BadDataset, MissingFileIsNamed) {
  write("test_ic_19647.txt", kTwoObjects);
  EXPECT_NE(error().find("test_par_19647.txt: cannot open"), std::string::npos) << error();
}

TEST_F(BadDataset, WrongCountIsNamed) {
  write("test_ic_19647.txt", kTwoObjects);
  write("test_par_19647.txt", "1e-11\n");
  EXPECT_NE(error().find("test_par_19647.txt: 1 values for 2 objects"), std::string::npos) << error();
  write("test_ic_19647.txt", "7000000\n0\n0\n");
  EXPECT_NE(error().find("not a multiple of 7"), std::string::npos) << error();
}

TEST_F(BadDataset, BadNumberNamesFileAndLine) {
  write("test_ic_19647.txt", "7000000\n0\nabc\n0\n7500\n0\n0.5\n");
  write("test_par_19647.txt", "1e-11\n");
  EXPECT_NE(error().find("test_ic_19647.txt:3: not a finite number: 'abc'"), std::string::npos) << error();
  write("test_ic_19647.txt", "7000000\n0\nnan\n0\n7500\n0\n0.5\n");
  EXPECT_NE(error().find("test_ic_19647.txt:3"), std::string::npos) << error();
}

TEST_F(BadDataset, UnsoundObjectsNameObjectAndField) {
  write("test_par_19647.txt", "1e-11\n1e-11\n");
  write("test_ic_19647.txt", "7000000\n0\n0\n0\n7500\n0\n0.5\n0\n7100000\n0\n-7400\n0\n0\n-0.05\n");
  EXPECT_NE(error().find("object 2: radius must be positive"), std::string::npos) << error();
  write("test_ic_19647.txt", "7000000\n0\n0\n0\n7500\n0\n0.5\n0\n6000000\n0\n-7400\n0\n0\n0.05\n");
  EXPECT_NE(error().find("object 2 (LEO19647-2): position is below the Earth's surface"), std::string::npos)
      << error();
  write("test_ic_19647.txt", kTwoObjects);
  write("test_par_19647.txt", "1e-11\n-1e-11\n");
  EXPECT_NE(error().find("test_par_19647.txt:2: object 2: drag parameter must be non-negative"),
            std::string::npos)
      << error();
  write("test_par_19647.txt", "1e-11\n1e-11\n");
  EXPECT_EQ(error(), "");
}

ObjectRecord sound(ObjectId id) {
  ObjectRecord r;
  r.id = id;
  r.position_m = {7.0e6, 0.0, 0.0};
  r.velocity_m_s = {0.0, 7.5e3, 0.0};
  r.radius_m = 0.5;
  r.mass_kg = 100.0;
  r.drag_area_to_mass_m2_kg = 0.01;
  r.srp_area_to_mass_m2_kg = 0.005;
  return r;
}

std::string refusal(const ObjectRecord& bad) {
  Population p;
  p.add(sound(1));
  p.add(bad);
  try {
    validate_for_propagation(p);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(BadInput, PropagationRefusesUnsoundObjectsNamingObjectAndField) {
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  ObjectRecord r = sound(9);
  r.position_m.y() = nan;
  EXPECT_EQ(refusal(r), "object 9: position is not finite");
  r = sound(9);
  r.velocity_m_s.z() = inf;
  EXPECT_EQ(refusal(r), "object 9: velocity is not finite");
  r = sound(9);
  r.position_m = {6.0e6, 0, 0};
  EXPECT_EQ(refusal(r), "object 9: position is below the Earth's surface");
  r = sound(9);
  r.radius_m = -1;
  EXPECT_EQ(refusal(r), "object 9: radius_m must be positive");
  r = sound(9);
  r.mass_kg = -1;
  EXPECT_EQ(refusal(r), "object 9: mass_kg must be positive");
  r = sound(9);
  r.drag_area_to_mass_m2_kg = -0.1;
  EXPECT_EQ(refusal(r), "object 9: drag_area_to_mass_m2_kg must be finite and non-negative");
  r = sound(9);
  r.srp_area_to_mass_m2_kg = -0.1;
  EXPECT_EQ(refusal(r), "object 9: srp_area_to_mass_m2_kg must be finite and non-negative");
  EXPECT_EQ(refusal(sound(9)), "");
}

TEST(BadInput, StepRefusesBadStepsAndRaggedArrays) {
  Population p;
  p.add(sound(1));
  SymplecticPropagator propagator(ForceModelSettings{}, leo19647_epoch());
  EXPECT_THROW(propagator.step(p, 0.0, 0.0), std::invalid_argument);
  EXPECT_THROW(propagator.step(p, 0.0, -10.0), std::invalid_argument);
  EXPECT_THROW(propagator.step(p, 0.0, std::numeric_limits<double>::quiet_NaN()), std::invalid_argument);
  p.mass_kg.clear();
  EXPECT_NO_THROW(propagator.step(p, 0.0, 10.0));  // mass is not used by the force model
  p.state.vx.pop_back();
  EXPECT_THROW(propagator.step(p, 0.0, 10.0), std::invalid_argument);
}

TEST(BurnUp, ObjectsBelowTheMinimumAltitudeAreReportedAndFlagged) {
  Population p;
  const double re = constants::kEarthEquatorialRadius_m;
  for (ObjectId id = 1; id <= 5; ++id) p.add(sound(id));
  // The last object's state is broken (NaN): it leaves as well.
  p.state.x = {re + 400e3, re + 149e3, re + 151e3, re + 100e3, std::nan("")};
  std::vector<char> flags;
  const auto events = find_burn_ups(p, 150e3, 42.0, flags);
  ASSERT_EQ(events.size(), 3u);
  EXPECT_EQ(events[0].id, 2u);
  EXPECT_EQ(events[1].id, 4u);
  EXPECT_EQ(events[2].id, 5u);
  EXPECT_EQ(events[0].time_s, 42.0);
  EXPECT_NEAR(events[0].altitude_m, 149e3, 1e-6);
  EXPECT_EQ(flags, (std::vector<char>{0, 1, 0, 1, 1}));
  p.remove_flagged(flags);
  EXPECT_EQ(p.id, (std::vector<ObjectId>{1, 3}));
}

}  // namespace
}  // namespace kessler
