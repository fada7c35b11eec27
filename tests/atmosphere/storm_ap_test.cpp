// Why the force model feeds NRLMSISE-00 the daily Ap and not the 3-hour history (switch 9 = -1): over a
// whole storm the two give nearly the same integrated density, which is what decay integrates; only the
// timing within the storm differs (the history lags the daily mean by hours). Measured on the two largest
// storms in SW-All.csv's cycle 23-25 record: 2003-10-28 .. 11-02 (Halloween, Ap up to 204) and
// 2024-05-10 .. 05-14 (Ap up to 271), global mean density at 400 and 800 km.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "core/catalog/bundled_datasets.hpp"
#include "core/physics/nrlmsise00/nrlmsise00.hpp"

namespace kessler {
namespace {

// SW-All.csv's daily rows: AP1..AP8, AP_AVG, F10.7_OBS, F10.7_OBS_CENTER81, in file order.
struct ApTable {
  std::vector<std::string> dates;
  std::vector<std::vector<double>> rows;
  int index_of(const std::string& date) const {
    for (std::size_t i = 0; i < dates.size(); ++i)
      if (dates[i] == date) return static_cast<int>(i);
    return -1;
  }
  // The 3-hour ap of block b (0..7) of day d; b may run into earlier days.
  double ap3(int d, int b) const {
    while (b < 0) b += 8, --d;
    return rows[d][b];
  }
};

ApTable read_ap_table() {
  ApTable t;
  std::ifstream in(default_datasets_dir() + "/space_weather/SW-All.csv");
  std::string line;
  std::getline(in, line);
  while (std::getline(in, line)) {
    std::vector<std::string> f;
    std::stringstream fields(line);
    for (std::string x; std::getline(fields, x, ',');) f.push_back(x);
    if (f.size() < 28 || f[12].empty() || f[24].empty() || f[27].empty()) continue;
    std::vector<double> v;
    for (int k = 12; k <= 20; ++k) v.push_back(std::stod(f[k]));
    v.push_back(std::stod(f[24]));
    v.push_back(std::stod(f[27]));
    t.dates.push_back(f[0]);
    t.rows.push_back(v);
  }
  return t;
}

struct DayDensity {
  double daily_ap = 0.0, three_hour = 0.0;  // sums of the global mean density over the day's hours
};

// The global mean drag density at h_km over each hour of day d, with daily Ap and with the 3-hour history.
DayDensity day_density(const ApTable& t, int d, double h_km) {
  std::array<int, 24> on{};
  on.fill(1);
  std::array<int, 24> history = on;
  history[9] = -1;
  const nrlmsise00::Switches daily_switches = nrlmsise00::Switches::from(on);
  const nrlmsise00::Switches history_switches = nrlmsise00::Switches::from(history);
  DayDensity out;
  for (int hour = 0; hour < 24; ++hour) {
    const int block = hour / 3;
    double m12 = 0.0, m36 = 0.0;
    for (int k = 4; k <= 11; ++k) m12 += t.ap3(d, block - k) / 8.0;
    for (int k = 12; k <= 19; ++k) m36 += t.ap3(d, block - k) / 8.0;
    for (int lat = -75; lat <= 75; lat += 25)
      for (int lst = 0; lst < 24; lst += 3) {
        MsisInput in;
        in.day_of_year = 300;
        in.ut_s = hour * 3600.0 + 1800.0;
        in.altitude_km = h_km;
        in.latitude_deg = lat;
        in.local_solar_time_h = lst;
        in.longitude_deg = std::fmod((lst - in.ut_s / 3600.0) * 15.0 + 720.0, 360.0);
        in.f107 = t.rows[d - 1][9];
        in.f107_avg = t.rows[d][10];
        in.ap = t.rows[d][8];
        in.ap_history = {
            t.rows[d][8], t.ap3(d, block), t.ap3(d, block - 1), t.ap3(d, block - 2), t.ap3(d, block - 3), m12,
            m36};
        out.daily_ap += nrlmsise00_density(in, daily_switches).rho_drag_kg_m3;
        out.three_hour += nrlmsise00_density(in, history_switches).rho_drag_kg_m3;
      }
  }
  return out;
}

TEST(StormAp, DailyApGivesAStormsIntegratedDensityWithinAFewPercent) {
  const ApTable t = read_ap_table();
  for (const auto& [first, days] :
       std::vector<std::pair<std::string, int>>{{"2003-10-28", 6}, {"2024-05-10", 5}}) {
    const int d0 = t.index_of(first);
    ASSERT_GT(d0, 2) << first;
    for (double h : {400.0, 800.0}) {
      double daily = 0.0, history = 0.0, widest_day = 0.0;
      for (int d = d0; d < d0 + days; ++d) {
        const DayDensity day = day_density(t, d, h);
        daily += day.daily_ap;
        history += day.three_hour;
        widest_day = std::max(widest_day, std::fabs(day.three_hour / day.daily_ap - 1.0));
      }
      std::printf(
          "storm from %s, %.0f km: 3-hour / daily Ap, whole storm %.3f; one day up to %.0f %% apart\n",
          first.c_str(), h, history / daily, 100.0 * widest_day);
      EXPECT_NEAR(history / daily, 1.0, 0.08);  // the storm's total
      EXPECT_GT(widest_day, 0.10);              // the timing within it
    }
  }
}

}  // namespace
}  // namespace kessler
