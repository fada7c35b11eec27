// NRLMSISE-00 against the model's 17 standard test cases (tests/data/nrlmsise00/test_cases.json, as
// printed by the model's public distribution): every species' number density, the total mass density
// and both temperatures, each to 1e-6 relative (the printed values carry 7 significant digits, so a
// printed value is within 5e-7 relative of the exact one, plus rounding in the comparison).
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/physics/nrlmsise00/nrlmsise00.hpp"

namespace kessler {
namespace {

// The file's cases, read with a small scanner (the file's layout: one object per case, "key": value).
struct Case {
  MsisInput input;
  int switch_9 = 1;
  std::vector<std::pair<std::string, double>> expected;
};

double number_after(const std::string& text, const std::string& key, std::size_t from = 0) {
  const std::size_t at = text.find("\"" + key + "\":", from);
  if (at == std::string::npos) throw std::runtime_error("no key " + key);
  return std::strtod(text.c_str() + at + key.size() + 3, nullptr);
}

std::vector<Case> read_cases() {
  std::ifstream file(std::string(KESSLER_TEST_DATA_DIR) + "/nrlmsise00/test_cases.json");
  std::stringstream buffer;
  buffer << file.rdbuf();
  const std::string all = buffer.str();
  std::vector<Case> cases;
  for (std::size_t at = all.find("{\n   \"doy\""); at != std::string::npos;
       at = all.find("{\n   \"doy\"", at + 1)) {
    const std::size_t end = all.find("}\n  }", at);
    const std::string text = all.substr(at, end - at);
    Case c;
    c.input.day_of_year = static_cast<int>(number_after(text, "doy"));
    c.input.ut_s = number_after(text, "sec");
    c.input.altitude_km = number_after(text, "alt_km");
    c.input.latitude_deg = number_after(text, "g_lat_deg");
    c.input.longitude_deg = number_after(text, "g_long_deg");
    c.input.local_solar_time_h = number_after(text, "lst_h");
    c.input.f107_avg = number_after(text, "f107A");
    c.input.f107 = number_after(text, "f107");
    c.input.ap = number_after(text, "ap");
    c.switch_9 = static_cast<int>(number_after(text, "switch_9"));
    const std::size_t array = text.find("\"ap_array\": [");
    if (array != std::string::npos) {
      const char* p = text.c_str() + array + 13;
      for (double& a : c.input.ap_history) {
        char* next = nullptr;
        a = std::strtod(p, &next);
        p = next + 1;  // past the comma
      }
    }
    const std::size_t expected = text.find("\"expected\"");
    for (const char* key :
         {"He", "O", "N2", "O2", "Ar", "rho_g_cm3", "H", "N", "anomalous_O", "T_exospheric_K", "T_at_alt_K"})
      c.expected.emplace_back(key, number_after(text, key, expected));
    cases.push_back(c);
  }
  return cases;
}

// The model's value in the file's units (cm^-3, g/cm^3, K).
double value_of(const MsisOutput& out, const std::string& key) {
  if (key == "He") return out.he * 1e-6;
  if (key == "O") return out.o * 1e-6;
  if (key == "N2") return out.n2 * 1e-6;
  if (key == "O2") return out.o2 * 1e-6;
  if (key == "Ar") return out.ar * 1e-6;
  if (key == "H") return out.h * 1e-6;
  if (key == "N") return out.n * 1e-6;
  if (key == "anomalous_O") return out.anomalous_o * 1e-6;
  if (key == "rho_g_cm3") return out.rho_kg_m3 * 1e-3;
  if (key == "T_exospheric_K") return out.exospheric_temperature_k;
  return out.temperature_k;
}

constexpr double kRelativeTolerance = 1.0e-6;

TEST(Nrlmsise00, SeventeenStandardCases) {
  const std::vector<Case> cases = read_cases();
  ASSERT_EQ(cases.size(), 17u);
  double worst = 0.0;
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const Case& c = cases[i];
    std::array<int, 24> settings;
    settings.fill(1);
    settings[0] = 0;
    settings[9] = c.switch_9;
    const MsisOutput out = nrlmsise00_density(c.input, nrlmsise00::Switches::from(settings));
    for (const auto& [key, expected] : c.expected) {
      const double got = value_of(out, key);
      if (expected == 0.0) {
        EXPECT_EQ(got, 0.0) << "case " << i + 1 << " " << key;
        continue;
      }
      if (key == "anomalous_O" && expected < 1e-30) {
        // Case 4 and 16 (100 km): anomalous O underflows in single precision (the FORTRAN package prints
        // 0); in double precision it is ~2.8e-42 cm^-3, 53 orders below O there. Negligible either way.
        EXPECT_LT(got, 1e-30) << "case " << i + 1 << " " << key;
        EXPECT_NEAR(got / expected, 1.0, 1e-4) << "case " << i + 1 << " " << key;
        continue;
      }
      const double rel = std::fabs(got / expected - 1.0);
      worst = std::max(worst, rel);
      EXPECT_LT(rel, kRelativeTolerance)
          << "case " << i + 1 << " " << key << ": " << got << " vs " << expected;
    }
  }
  std::printf("worst relative difference over the 17 cases: %.3g\n", worst);
}

TEST(Nrlmsise00, DragDensityAddsAnomalousOxygen) {
  MsisInput in;
  in.day_of_year = 172;
  in.ut_s = 29000;
  in.altitude_km = 800;
  in.latitude_deg = 60;
  in.longitude_deg = -70;
  in.local_solar_time_h = 16;
  const MsisOutput out = nrlmsise00_density(in);
  EXPECT_NEAR(out.rho_drag_kg_m3 - out.rho_kg_m3, 16.0 * 1.66e-27 * out.anomalous_o, 1e-12 * out.rho_kg_m3);
  EXPECT_GT(out.rho_drag_kg_m3, out.rho_kg_m3);
}

}  // namespace
}  // namespace kessler

namespace kessler {
namespace {

// One column's expansions reused at many altitudes (the grid's build) give the full model's bits.
TEST(Nrlmsise00, ColumnGivesTheFullModelsBits) {
  MsisInput in;
  in.day_of_year = 300;
  in.ut_s = 5000;
  in.latitude_deg = -35;
  in.longitude_deg = 120;
  in.local_solar_time_h = 21;
  in.f107 = 200;
  in.f107_avg = 180;
  in.ap = 30;
  const nrlmsise00::ColumnTerms column(in, nrlmsise00::Switches::all_on());
  for (double h :
       {90.0, 100.0, 119.0, 121.0, 155.0, 199.0, 299.0, 301.0, 449.0, 451.0, 800.0, 2000.0, 140.0, 95.0}) {
    MsisInput at = in;
    at.altitude_km = h;
    const MsisOutput full = nrlmsise00_density(at);
    const MsisOutput fast = column.at(h);
    EXPECT_EQ(full.rho_drag_kg_m3, fast.rho_drag_kg_m3) << h;
    EXPECT_EQ(full.o, fast.o) << h;
    EXPECT_EQ(full.temperature_k, fast.temperature_k) << h;
  }
}

}  // namespace
}  // namespace kessler
