// The space-weather table (deploy/datasets/space_weather/SW-All.csv): values on known dates, the
// predicted months, the cycle and constant modes, and files with gaps or garbled fields refused with the
// line and field named.
#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

#include "core/physics/space_weather.hpp"

namespace kessler {
namespace {

const SpaceWeather& table() {
  return *SpaceWeather::bundled();
}

TEST(SpaceWeather, BundledTableSpan) {
  EXPECT_EQ(table().first_day(), day_number(1957, 10, 1));
  EXPECT_EQ(table().last_daily_day(), day_number(2025, 5, 7));
  EXPECT_EQ(table().last_day(), day_number(2041, 10, 1));
  EXPECT_EQ(table().digest().size(), 64u);
  EXPECT_GT(table().predicted_ap(), 5.0);
  EXPECT_LT(table().predicted_ap(), 20.0);
}

TEST(SpaceWeather, ObservedValuesOnKnownDates) {
  // 2001-11-01: F10.7_OBS 235.6, F10.7_OBS_CENTER81 220.1, AP_AVG 24; 2008-06-01: 66.6, 67.2, 7.
  const DailySolarActivity nov1 = table().observed(day_number(2001, 11, 1));
  EXPECT_EQ(nov1.f107_avg, 220.1);
  EXPECT_EQ(nov1.ap, 24.0);
  EXPECT_EQ(table().observed(day_number(2001, 11, 2)).f107, 235.6);  // the previous day's flux
  const DailySolarActivity jun1 = table().observed(day_number(2008, 6, 1));
  EXPECT_EQ(jun1.f107_avg, 67.2);
  EXPECT_EQ(jun1.ap, 7.0);
  EXPECT_EQ(table().observed(day_number(2008, 6, 2)).f107, 66.6);
  // 2025-03-24 (last observed): 156.0; the next day is a daily prediction (PRD, Ap 29).
  EXPECT_EQ(table().observed(day_number(2025, 3, 25)).f107, 156.0);
  EXPECT_EQ(table().observed(day_number(2025, 3, 25)).ap, 29.0);
}

TEST(SpaceWeather, PredictedMonthsInterpolateAndUseTheCycleMeanAp) {
  // Monthly rows: 2025-07-01 F10.7 168.1 (81-day 169.7), 2025-08-01 165.5 (167.3).
  EXPECT_EQ(table().observed(day_number(2025, 7, 1)).f107_avg, 169.7);
  EXPECT_EQ(table().observed(day_number(2025, 7, 2)).f107, 168.1);
  const DailySolarActivity mid = table().observed(day_number(2025, 7, 16));
  EXPECT_NEAR(mid.f107_avg, 169.7 + 15.0 / 31.0 * (167.3 - 169.7), 1e-12);
  EXPECT_EQ(mid.ap, table().predicted_ap());
}

TEST(SpaceWeather, CycleModeRepeatsCycles23And24) {
  const std::int64_t start = day_number(1996, 8, 1), end = day_number(2019, 12, 1);
  EXPECT_EQ(end - start, 8522);
  for (std::int64_t offset : {0, 1, 2000, 8521}) {
    const DailySolarActivity a = table().cycle(end + offset);
    const DailySolarActivity b = table().observed(start + offset);
    EXPECT_EQ(a.f107, b.f107);
    EXPECT_EQ(a.f107_avg, b.f107_avg);
    EXPECT_EQ(a.ap, b.ap);
    EXPECT_EQ(table().cycle(end + offset + 8522).f107_avg, a.f107_avg);
    EXPECT_EQ(table().cycle(end + offset - 3 * 8522).f107_avg, a.f107_avg);
  }
  // Past the predictions the observed mode continues with the cycle.
  const std::int64_t later = day_number(2045, 1, 1);
  EXPECT_EQ(table().observed(later).f107_avg, table().cycle(later).f107_avg);
  SolarActivitySettings constant{SolarActivityMode::kConstant, 120.0, 9.0};
  const DailySolarActivity c = table().on_day(later, constant);
  EXPECT_EQ(c.f107, 120.0);
  EXPECT_EQ(c.f107_avg, 120.0);
  EXPECT_EQ(c.ap, 9.0);
}

const char* kHeader =
    "DATE,BSRN,ND,KP1,KP2,KP3,KP4,KP5,KP6,KP7,KP8,KP_SUM,AP1,AP2,AP3,AP4,AP5,AP6,AP7,AP8,AP_AVG,CP,C9,ISN,"
    "F10.7_OBS,F10.7_ADJ,F10.7_DATA_TYPE,F10.7_OBS_CENTER81,F10.7_OBS_LAST81,F10.7_ADJ_CENTER81,"
    "F10.7_ADJ_LAST81\n";

std::string row(const std::string& date, const std::string& ap, const std::string& f107,
                const std::string& type, const std::string& avg) {
  return date + ",1,1,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0," + ap + ",0,0,0," + f107 + ",1," + type + "," + avg +
         ",1,1,1\n";
}

std::string refusal(const std::string& csv) {
  try {
    SpaceWeather::parse(csv, "SW-test.csv");
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "accepted";
}

TEST(SpaceWeather, GoodSmallFileParses) {
  const std::string csv = std::string(kHeader) + row("2020-01-30", "5", "70.1", "OBS", "71.0") +
                          row("2020-01-31", "6", "70.2", "OBS", "71.1") +
                          row("2020-02-01", "", "72.0", "PRM", "72.5") +
                          row("2020-03-01", "", "74.0", "PRM", "73.5");
  const SpaceWeather t = SpaceWeather::parse(csv, "SW-test.csv");
  EXPECT_EQ(t.last_day(), day_number(2020, 3, 1));
  EXPECT_EQ(t.observed(day_number(2020, 1, 31)).f107, 70.1);
  EXPECT_EQ(t.observed(day_number(2020, 2, 1)).ap, 5.5);
}

TEST(SpaceWeather, GappedOrGarbledFilesAreRefusedWithLineAndField) {
  const std::string head = std::string(kHeader) + row("2020-01-01", "5", "70.1", "OBS", "71.0");
  EXPECT_EQ(refusal(head + row("2020-01-03", "5", "70.1", "OBS", "71.0")),
            "SW-test.csv line 3: DATE: 2020-01-03 does not follow the previous row's day (1 day(s) missing)");
  EXPECT_EQ(refusal(head + row("2020-01-01", "5", "70.1", "OBS", "71.0")),
            "SW-test.csv line 3: DATE: 2020-01-01 does not follow the previous row's day (out of order)");
  EXPECT_EQ(refusal(head + row("2020-01-02", "5", "7x.1", "OBS", "71.0")),
            "SW-test.csv line 3: F10.7_OBS: '7x.1' is not a number");
  EXPECT_EQ(refusal(head + row("2020-01-02", "", "70.1", "OBS", "71.0")),
            "SW-test.csv line 3: AP_AVG: empty");
  EXPECT_EQ(refusal(head + row("2020-01-02", "5", "70.1", "OBS", "-3")),
            "SW-test.csv line 3: F10.7_OBS_CENTER81: -3 is out of range (below 0.000000)");
  EXPECT_EQ(refusal(head + row("2020-1-02", "5", "70.1", "OBS", "71")),
            "SW-test.csv line 3: DATE: '2020-1-02' is not a date YYYY-MM-DD");
  EXPECT_EQ(refusal(head + row("2020-01-02", "5", "70.1", "XYZ", "71")),
            "SW-test.csv line 3: F10.7_DATA_TYPE: 'XYZ' is not OBS, INT, PRD or PRM");
  EXPECT_EQ(refusal(head + row("2020-03-01", "", "70.1", "PRM", "71")),
            "SW-test.csv line 3: DATE: 2020-03-01 does not follow the previous month");
  EXPECT_EQ(refusal(head + "2020-01-02,1,2\n"),
            "SW-test.csv line 3: row: 3 fields, the header names 28 or more");
  EXPECT_EQ(refusal("DATE,AP_AVG\n"), "SW-test.csv line 1: F10.7_OBS: no such column in the header");
}

}  // namespace
}  // namespace kessler
