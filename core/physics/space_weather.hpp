// Solar and geomagnetic activity for the atmosphere (NRLMSISE-00): F10.7 of the previous day, its 81-day
// centred mean, and the daily Ap, per UTC day, from CelesTrak's SW-All.csv (data from NOAA SWPC;
// deploy/datasets/space_weather/, see its README).
//
// The table: daily rows (OBS observed, INT interpolated, PRD predicted) must follow each other day by
// day; monthly predicted rows (PRM, dated the 1st) follow them month by month. A file with a gap, a row
// out of order or a field that does not parse is refused (std::runtime_error naming the line and field).
//
// Three modes (SolarActivitySettings):
//  - kObserved: the table. Daily rows as they are; between the last daily row and the monthly rows, and
//    between monthly rows, F10.7 and its 81-day mean are interpolated linearly in time between the rows'
//    dates (the monthly value taken at the 1st of its month); the monthly rows carry no Ap, so Ap there is
//    the mean daily Ap of the last 4018 daily rows (11 years, one solar cycle; 11.3 in SW-All.csv).
//    Outside the table (before its first or after its last row) the cycle mode below.
//  - kCycle: a repeating solar cycle built from the observed cycles 23 and 24: the daily rows from the
//    minimum of 1996-08-01 to the minimum of 2019-12-01 (8522 days, two cycles of 12.3 and 11.0 years),
//    repeated with period 8522 days and phased so that 2019-12-01 (the minimum that starts cycle 25) falls
//    on 1996-08-01: every date maps into that window (day - 2019-12-01 modulo 8522 days, added to
//    1996-08-01), and the observed values there are used.
//  - kConstant: F10.7 = its 81-day mean = f107, Ap = ap.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "core/time/epoch.hpp"

namespace kessler {

enum class SolarActivityMode { kObserved, kCycle, kConstant };

struct SolarActivitySettings {
  SolarActivityMode mode = SolarActivityMode::kObserved;
  double f107_sfu = 150.0;  // kConstant: F10.7 and its 81-day mean
  double ap = 15.0;         // kConstant: daily Ap
};

// NRLMSISE-00's solar inputs for one UTC day.
struct DailySolarActivity {
  double f107 = 0.0;      // F10.7 of the previous day [sfu]
  double f107_avg = 0.0;  // 81-day centred mean of F10.7 on the day [sfu]
  double ap = 0.0;        // daily Ap
};

// Days since 1970-01-01 of a proleptic Gregorian date, and of the UTC day that holds an instant.
std::int64_t day_number(int year, int month, int day);
std::int64_t day_number(const UtcEpoch& when);

class SpaceWeather {
 public:
  // The table in CSV text (`name` for messages, e.g. "SW-All.csv"). Throws std::runtime_error
  // "<name> line <n>: <field>: <reason>" on a gap, a row out of order or a field that does not parse.
  static SpaceWeather parse(std::string_view csv, const std::string& name);
  // From a file; throws std::runtime_error when it cannot be read or parsed.
  static SpaceWeather load(const std::string& path);
  // deploy/datasets/space_weather/SW-All.csv under default_datasets_dir(), loaded once and shared.
  static std::shared_ptr<const SpaceWeather> bundled();
  // <datasets_dir>/space_weather/SW-All.csv, loaded once per directory and shared; throws as load().
  static std::shared_ptr<const SpaceWeather> in_datasets(const std::string& datasets_dir);

  // The inputs on UTC day `day` (day_number) in the given mode.
  DailySolarActivity on_day(std::int64_t day, const SolarActivitySettings& settings) const;
  DailySolarActivity observed(std::int64_t day) const;
  DailySolarActivity cycle(std::int64_t day) const;

  std::int64_t first_day() const { return first_day_; }
  std::int64_t last_daily_day() const { return first_day_ + static_cast<std::int64_t>(daily_.size()) - 1; }
  std::int64_t last_day() const { return monthly_.empty() ? last_daily_day() : monthly_.back().day; }
  double predicted_ap() const { return predicted_ap_; }
  // SHA-256 of the file's text (hex): identifies the table in a run's configuration key.
  const std::string& digest() const { return digest_; }

  static constexpr int kCycleStart[3] = {1996, 8, 1};  // minimum before cycle 23
  static constexpr int kCycleEnd[3] = {2019, 12, 1};   // minimum before cycle 25

 private:
  struct Row {
    std::int64_t day;
    double f107, f107_avg, ap;
  };
  // The values (not yet shifted to "previous day") at `day` inside [first_day, last_day].
  Row row_at(std::int64_t day) const;
  std::int64_t first_day_ = 0;
  std::vector<Row> daily_;    // consecutive days from first_day_
  std::vector<Row> monthly_;  // consecutive months after the daily rows
  double predicted_ap_ = 0.0;
  std::string digest_;
};

}  // namespace kessler
