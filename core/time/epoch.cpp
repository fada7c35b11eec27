#include "core/time/epoch.hpp"

#include <cmath>
#include <cstdio>
#include <numbers>

namespace kessler {
namespace {

constexpr double kSecondsPerDay = 86400.0;

// Julian date at 0h of a Gregorian calendar date (Vallado, "Fundamentals of Astrodynamics", alg. 14;
// valid 1900..2100, which covers every catalog epoch).
double julian_day_at_midnight(int year, int month, int day) {
  return 367.0 * year - std::floor((7 * (year + std::floor((month + 9) / 12.0))) * 0.25) +
         std::floor(275 * month / 9.0) + day + 1721013.5;
}

bool is_leap(int year) {
  return (year % 4 == 0 && year % 100 != 0) || year % 400 == 0;
}

int days_in_month(int year, int month) {
  static constexpr int kDays[] = {31, 28, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31};
  return month == 2 && is_leap(year) ? 29 : kDays[month - 1];
}

}  // namespace

UtcEpoch::UtcEpoch(double whole, double fraction) {
  // Normalise so that jd_fraction is in [0, 1) and jd_whole ends in .5 (midnight).
  double shift = std::floor(fraction);
  whole += shift;
  fraction -= shift;
  double whole_mid = std::floor(whole - 0.5) + 0.5;
  fraction += whole - whole_mid;
  shift = std::floor(fraction);
  jd_whole_ = whole_mid + shift;
  jd_fraction_ = fraction - shift;
}

UtcEpoch UtcEpoch::from_julian_date(double jd_whole, double jd_fraction) {
  return {jd_whole, jd_fraction};
}

UtcEpoch UtcEpoch::from_calendar(int year, int month, int day, int hour, int minute, double second) {
  double fraction = (hour * 3600.0 + minute * 60.0 + second) / kSecondsPerDay;
  return {julian_day_at_midnight(year, month, day), fraction};
}

UtcEpoch UtcEpoch::from_year_and_day_of_year(int year, double day_of_year) {
  if (year < 100) year += year < 57 ? 2000 : 1900;
  double whole_day = std::floor(day_of_year);
  // January 1 is day 1.
  return {julian_day_at_midnight(year, 1, 1) + (whole_day - 1.0), day_of_year - whole_day};
}

std::optional<UtcEpoch> UtcEpoch::parse_iso8601(std::string_view text, std::string* error) {
  auto fail = [&](const char* why) -> std::optional<UtcEpoch> {
    if (error) *error = std::string("not an ISO 8601 UTC date (") + why + "): '" + std::string(text) + "'";
    return std::nullopt;
  };
  auto digits = [&](size_t pos, size_t n, int& out) {
    if (pos + n > text.size()) return false;
    out = 0;
    for (size_t i = pos; i < pos + n; ++i) {
      if (text[i] < '0' || text[i] > '9') return false;
      out = out * 10 + (text[i] - '0');
    }
    return true;
  };
  int year, month, day, hour = 0, minute = 0, whole_second = 0;
  if (!digits(0, 4, year) || text.size() < 10 || text[4] != '-' || !digits(5, 2, month) || text[7] != '-' ||
      !digits(8, 2, day))
    return fail("expected YYYY-MM-DD");
  size_t pos = 10;
  double second = 0.0;
  if (pos < text.size() && (text[pos] == 'T' || text[pos] == ' ')) {
    if (!digits(pos + 1, 2, hour) || pos + 3 >= text.size() || text[pos + 3] != ':' ||
        !digits(pos + 4, 2, minute))
      return fail("expected hh:mm after the date");
    pos += 6;
    if (pos < text.size() && text[pos] == ':') {
      if (!digits(pos + 1, 2, whole_second)) return fail("expected ss");
      pos += 3;
      second = whole_second;
      if (pos < text.size() && text[pos] == '.') {
        double scale = 0.1;
        ++pos;
        if (pos >= text.size() || text[pos] < '0' || text[pos] > '9')
          return fail("expected digits after '.'");
        while (pos < text.size() && text[pos] >= '0' && text[pos] <= '9') {
          second += (text[pos] - '0') * scale;
          scale *= 0.1;
          ++pos;
        }
      }
    }
  }
  if (pos < text.size() && text[pos] == 'Z') ++pos;
  if (pos != text.size()) return fail("unexpected trailing text");
  if (month < 1 || month > 12) return fail("month out of range");
  if (day < 1 || day > days_in_month(year, month)) return fail("day out of range");
  if (hour > 23 || minute > 59 || second >= 61.0) return fail("time of day out of range");
  if (year < 1900 || year > 2199) return fail("year outside 1900..2199");
  return from_calendar(year, month, day, hour, minute, second);
}

UtcEpoch UtcEpoch::plus_seconds(double dt_s) const {
  return {jd_whole_, jd_fraction_ + dt_s / kSecondsPerDay};
}

double UtcEpoch::seconds_since(const UtcEpoch& origin) const {
  return ((jd_whole_ - origin.jd_whole_) + (jd_fraction_ - origin.jd_fraction_)) * kSecondsPerDay;
}

void UtcEpoch::to_calendar(int& year, int& month, int& day, int& hour, int& minute, double& second) const {
  // Civil date from the Julian day number (Fliegel and Van Flandern), then the time of day.
  long jdn = static_cast<long>(jd_whole_ + 0.5);
  long l = jdn + 68569;
  long n = 4 * l / 146097;
  l = l - (146097 * n + 3) / 4;
  long i = 4000 * (l + 1) / 1461001;
  l = l - 1461 * i / 4 + 31;
  long j = 80 * l / 2447;
  day = static_cast<int>(l - 2447 * j / 80);
  l = j / 11;
  month = static_cast<int>(j + 2 - 12 * l);
  year = static_cast<int>(100 * (n - 49) + i + l);
  double seconds_of_day = jd_fraction_ * kSecondsPerDay;
  hour = static_cast<int>(seconds_of_day / 3600.0);
  minute = static_cast<int>((seconds_of_day - hour * 3600.0) / 60.0);
  second = seconds_of_day - hour * 3600.0 - minute * 60.0;
}

std::string UtcEpoch::to_iso8601(int decimals) const {
  if (decimals < 0) decimals = 0;
  if (decimals > 9) decimals = 9;
  // Round the time of day to whole units of the printed precision and split it in integers, so that
  // 59.9999 s never prints as 60.000 (a round trip through the day fraction can land an ulp below).
  long long per_second = 1;
  for (int k = 0; k < decimals; ++k) per_second *= 10;
  const long long per_day = 86400LL * per_second;
  long long units = std::llround(jd_fraction_ * kSecondsPerDay * static_cast<double>(per_second));
  const long long day_carry = units >= per_day ? 1 : 0;  // jd_fraction_ is in [0, 1)
  units -= day_carry * per_day;
  int y, mo, d, h, mi;
  double s;
  UtcEpoch(jd_whole_ + static_cast<double>(day_carry), 0.0).to_calendar(y, mo, d, h, mi, s);
  h = static_cast<int>(units / (3600 * per_second));
  mi = static_cast<int>(units / (60 * per_second) % 60);
  const long long second_units = units % (60 * per_second);
  char buf[64];
  if (decimals == 0)
    std::snprintf(buf, sizeof buf, "%04d-%02d-%02dT%02d:%02d:%02lldZ", y, mo, d, h, mi, second_units);
  else
    std::snprintf(buf, sizeof buf, "%04d-%02d-%02dT%02d:%02d:%02lld.%0*lldZ", y, mo, d, h, mi,
                  second_units / per_second, decimals, second_units % per_second);
  return buf;
}

double UtcEpoch::gmst_rad() const {
  // IAU-82 GMST (Vallado, eq. 3-47), the angle SGP4's TEME frame is defined with.
  double t_ut1 = ((jd_whole_ - 2451545.0) + jd_fraction_) / 36525.0;
  double gmst_s = -6.2e-6 * t_ut1 * t_ut1 * t_ut1 + 0.093104 * t_ut1 * t_ut1 +
                  (876600.0 * 3600.0 + 8640184.812866) * t_ut1 + 67310.54841;
  double angle = std::fmod(gmst_s * (std::numbers::pi / 180.0) / 240.0, 2.0 * std::numbers::pi);
  if (angle < 0.0) angle += 2.0 * std::numbers::pi;
  return angle;
}

}  // namespace kessler
