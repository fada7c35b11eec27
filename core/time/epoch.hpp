// A UTC instant and the conversions every part of the core needs: calendar and ISO 8601 text, Julian
// dates, and the Earth's rotation angle (GMST) that links the inertial frame to the rotating Earth.
//
// Time scales: UTC throughout; UT1 - UTC (< 0.9 s) and leap seconds inside a run are ignored, as in the
// paper and in SGP4 practice. Simulation time is seconds since the scenario's start epoch (a double).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace kessler {

class UtcEpoch {
 public:
  // J2000.0 (2000-01-01T12:00:00 UTC) unless set otherwise.
  UtcEpoch() = default;

  // Julian date split in two parts for precision: jd_whole holds the integer-and-a-half day,
  // jd_fraction the rest in [0, 1).
  static UtcEpoch from_julian_date(double jd_whole, double jd_fraction);
  // Calendar date and time of day; second may carry a fraction. No range checks beyond basic sanity.
  static UtcEpoch from_calendar(int year, int month, int day, int hour, int minute, double second);
  // Two-digit-or-four-digit year and fractional day of year, as TLE epochs are written (day 1.0 =
  // January 1 00:00). Two-digit years follow the TLE convention: 57..99 -> 19xx, 00..56 -> 20xx.
  static UtcEpoch from_year_and_day_of_year(int year, double day_of_year);
  // "YYYY-MM-DDThh:mm:ss[.fff][Z]" (a space may replace the T; the Z is optional). Returns nullopt with
  // *error set to the reason when the text is not such a date.
  static std::optional<UtcEpoch> parse_iso8601(std::string_view text, std::string* error = nullptr);

  double jd_whole() const { return jd_whole_; }
  double jd_fraction() const { return jd_fraction_; }
  double julian_date() const { return jd_whole_ + jd_fraction_; }

  // The instant dt_s seconds later (dt_s may be negative).
  UtcEpoch plus_seconds(double dt_s) const;
  // Seconds from `origin` to this instant.
  double seconds_since(const UtcEpoch& origin) const;

  // Calendar fields of this instant.
  void to_calendar(int& year, int& month, int& day, int& hour, int& minute, double& second) const;
  // "YYYY-MM-DDThh:mm:ss.fffZ" with `decimals` digits of the second (0..9).
  std::string to_iso8601(int decimals = 3) const;

  // Greenwich mean sidereal time [rad, 0..2pi), IAU-82 model (as used with SGP4's TEME frame).
  double gmst_rad() const;

  friend bool operator==(const UtcEpoch& a, const UtcEpoch& b) {
    return a.jd_whole_ == b.jd_whole_ && a.jd_fraction_ == b.jd_fraction_;
  }

 private:
  UtcEpoch(double whole, double fraction);
  double jd_whole_ = 2451545.0;
  double jd_fraction_ = 0.0;
};

}  // namespace kessler
