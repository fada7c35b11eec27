#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "core/time/epoch.hpp"

namespace kessler {
namespace {

// A time of day that is a whole minute after a day-fraction round trip (16:48:00 reached by 30 s steps
// from 00:00, as the quickstart's progress printed "16:47:60.000") prints as the minute, at every
// precision, and the last instant of a day rolls over to the next date.
TEST(Epoch, WholeMinutesNeverPrintSixtySeconds) {
  const UtcEpoch start = UtcEpoch::from_calendar(2022, 1, 22, 0, 0, 0.0);
  for (int step = 0; step <= 2880; ++step) {
    const std::string text = start.plus_seconds(30.0 * step).to_iso8601(3);
    EXPECT_EQ(text.find(":60"), std::string::npos) << text;
  }
  EXPECT_EQ(start.plus_seconds(60480.0).to_iso8601(3), "2022-01-22T16:48:00.000Z");
  EXPECT_EQ(start.plus_seconds(86399.9996).to_iso8601(3), "2022-01-23T00:00:00.000Z");
  EXPECT_EQ(start.plus_seconds(86399.9996).to_iso8601(0), "2022-01-23T00:00:00Z");
  EXPECT_EQ(start.plus_seconds(1.25).to_iso8601(2), "2022-01-22T00:00:01.25Z");
}

TEST(UtcEpoch, J2000IsJulianDate2451545) {
  auto epoch = UtcEpoch::from_calendar(2000, 1, 1, 12, 0, 0.0);
  EXPECT_DOUBLE_EQ(epoch.julian_date(), 2451545.0);
}

TEST(UtcEpoch, GmstMatchesValladoExample3_5) {
  // Vallado, Fundamentals of Astrodynamics, example 3-5: 1992-08-20 12:14:00 UT1 -> GMST 152.578787886 deg.
  auto epoch = UtcEpoch::from_calendar(1992, 8, 20, 12, 14, 0.0);
  double gmst_deg = epoch.gmst_rad() * 180.0 / std::numbers::pi;
  EXPECT_NEAR(gmst_deg, 152.578787886, 1e-6);
}

TEST(UtcEpoch, TleEpochOfVerificationCase00005) {
  // SGP4-VER.TLE, satellite 00005: epoch 00179.78495062 is JD 2451723.28495062 (Vallado's jday).
  // 0.78495062 d = 67819.733568 s = 18:50:19.733568.
  auto epoch = UtcEpoch::from_year_and_day_of_year(0, 179.78495062);
  EXPECT_NEAR(epoch.julian_date(), 2451723.28495062, 1e-9);
  EXPECT_EQ(epoch.to_iso8601(3), "2000-06-27T18:50:19.734Z");
}

TEST(UtcEpoch, Iso8601RoundTrip) {
  std::string error;
  auto epoch = UtcEpoch::parse_iso8601("2022-01-01T00:00:00Z", &error);
  ASSERT_TRUE(epoch.has_value()) << error;
  EXPECT_EQ(epoch->to_iso8601(0), "2022-01-01T00:00:00Z");
  auto later = epoch->plus_seconds(86400.0 * 365.0 + 3661.5);
  EXPECT_EQ(later.to_iso8601(1), "2023-01-01T01:01:01.5Z");
  EXPECT_NEAR(later.seconds_since(*epoch), 86400.0 * 365.0 + 3661.5, 1e-5);
}

TEST(UtcEpoch, RefusesMalformedDates) {
  std::string error;
  EXPECT_FALSE(UtcEpoch::parse_iso8601("2022-13-01T00:00:00Z", &error));
  EXPECT_NE(error.find("month"), std::string::npos);
  EXPECT_FALSE(UtcEpoch::parse_iso8601("2022-02-30", &error));
  EXPECT_NE(error.find("day"), std::string::npos);
  EXPECT_FALSE(UtcEpoch::parse_iso8601("yesterday", &error));
  EXPECT_FALSE(UtcEpoch::parse_iso8601("2022-01-01T00:00:00Zjunk", &error));
}

}  // namespace
}  // namespace kessler
