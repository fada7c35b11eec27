#include "core/physics/space_weather.hpp"

#include <charconv>
#include <cmath>
#include <fstream>
#include <map>
#include <mutex>
#include <sstream>
#include <stdexcept>

#include "core/catalog/bundled_datasets.hpp"
#include "core/simulation/sha256.hpp"

namespace kessler {
namespace {

constexpr std::size_t kPredictedApDays = 4018;  // 11 years of daily rows

std::vector<std::string_view> split_commas(std::string_view line) {
  std::vector<std::string_view> fields;
  std::size_t start = 0;
  for (std::size_t i = 0; i <= line.size(); ++i) {
    if (i == line.size() || line[i] == ',') {
      fields.push_back(line.substr(start, i - start));
      start = i + 1;
    }
  }
  return fields;
}

// Reports "<name> line <n>: <field>: <reason>".
struct Reporter {
  const std::string& name;
  std::size_t line = 0;
  [[noreturn]] void fail(std::string_view field, const std::string& reason) const {
    throw std::runtime_error(name + " line " + std::to_string(line) + ": " + std::string(field) + ": " +
                             reason);
  }
};

double number(const Reporter& at, std::string_view field, std::string_view text, double minimum) {
  if (text.empty()) at.fail(field, "empty");
  double value = 0.0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc() || end != text.data() + text.size() || !std::isfinite(value))
    at.fail(field, std::string("'").append(text).append("' is not a number"));
  if (value < minimum)
    at.fail(field,
            std::string(text).append(" is out of range (below ").append(std::to_string(minimum)).append(")"));
  return value;
}

std::int64_t date(const Reporter& at, std::string_view text, int& day_of_month) {
  int y = 0, m = 0, d = 0;
  const bool shaped = text.size() == 10 && text[4] == '-' && text[7] == '-';
  auto part = [&](std::size_t from, std::size_t len, int& out) {
    const auto [end, error] = std::from_chars(text.data() + from, text.data() + from + len, out);
    return error == std::errc() && end == text.data() + from + len;
  };
  if (!shaped || !part(0, 4, y) || !part(5, 2, m) || !part(8, 2, d) || m < 1 || m > 12 || d < 1 || d > 31)
    at.fail("DATE", std::string("'").append(text).append("' is not a date YYYY-MM-DD"));
  day_of_month = d;
  return day_number(y, m, d);
}

std::int64_t next_month(std::int64_t day) {
  // The 1st of the month after the one holding `day`, by walking days (at most 31 steps).
  std::int64_t next = day + 1;
  while (true) {
    const UtcEpoch e = UtcEpoch::from_julian_date(2440587.5 + static_cast<double>(next), 0.0);
    int y, mo, d, h, mi;
    double s;
    e.to_calendar(y, mo, d, h, mi, s);
    if (d == 1) return next;
    ++next;
  }
}

}  // namespace

std::int64_t day_number(int year, int month, int day) {
  // Days from civil (H. Hinnant's algorithm): exact integer arithmetic.
  const int y = year - (month <= 2 ? 1 : 0);
  const int era = (y >= 0 ? y : y - 399) / 400;
  const int yoe = y - era * 400;
  const int doy = (153 * (month + (month > 2 ? -3 : 9)) + 2) / 5 + day - 1;
  const int doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
  return static_cast<std::int64_t>(era) * 146097 + doe - 719468;
}

std::int64_t day_number(const UtcEpoch& when) {
  // jd_whole is a whole day plus one half (midnight), jd_fraction in [0, 1).
  return static_cast<std::int64_t>(std::floor(when.jd_whole() - 2440587.5)) +
         static_cast<std::int64_t>(std::floor(when.jd_fraction()));
}

SpaceWeather SpaceWeather::parse(std::string_view csv, const std::string& name) {
  SpaceWeather table;
  Reporter at{name};
  std::size_t pos = 0;
  int col_date = -1, col_ap = -1, col_f107 = -1, col_avg = -1, col_type = -1;
  while (pos < csv.size()) {
    std::size_t end = csv.find('\n', pos);
    if (end == std::string_view::npos) end = csv.size();
    std::string_view line = csv.substr(pos, end - pos);
    pos = end + 1;
    ++at.line;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    if (line.empty()) continue;
    const std::vector<std::string_view> f = split_commas(line);
    if (col_date < 0) {  // the header
      for (int i = 0; i < static_cast<int>(f.size()); ++i) {
        const auto u = static_cast<std::size_t>(i);
        if (f[u] == "DATE") col_date = i;
        if (f[u] == "AP_AVG") col_ap = i;
        if (f[u] == "F10.7_OBS") col_f107 = i;
        if (f[u] == "F10.7_OBS_CENTER81") col_avg = i;
        if (f[u] == "F10.7_DATA_TYPE") col_type = i;
      }
      for (auto [col, field] :
           {std::pair{col_date, "DATE"}, std::pair{col_ap, "AP_AVG"}, std::pair{col_f107, "F10.7_OBS"},
            std::pair{col_avg, "F10.7_OBS_CENTER81"}, std::pair{col_type, "F10.7_DATA_TYPE"}})
        if (col < 0) at.fail(field, "no such column in the header");
      continue;
    }
    const int needed = std::max({col_date, col_ap, col_f107, col_avg, col_type});
    if (static_cast<int>(f.size()) <= needed)
      at.fail("row", std::to_string(f.size()) + " fields, the header names " + std::to_string(needed + 1) +
                         " or more");
    auto field = [&](int col) { return f[static_cast<std::size_t>(col)]; };
    int day_of_month = 0;
    const std::int64_t day = date(at, field(col_date), day_of_month);
    const std::string_view type = field(col_type);
    Row row{day, number(at, "F10.7_OBS", field(col_f107), 0.0),
            number(at, "F10.7_OBS_CENTER81", field(col_avg), 0.0), 0.0};
    if (type == "OBS" || type == "INT" || type == "PRD") {
      row.ap = number(at, "AP_AVG", field(col_ap), 0.0);
      if (!table.monthly_.empty()) at.fail("DATE", "a daily row after the monthly rows");
      if (table.daily_.empty()) {
        table.first_day_ = day;
      } else if (day != table.daily_.back().day + 1) {
        std::string reason(field(col_date));
        reason.append(" does not follow the previous row's day (");
        if (day <= table.daily_.back().day)
          reason.append("out of order)");
        else
          reason.append(std::to_string(day - table.daily_.back().day - 1)).append(" day(s) missing)");
        at.fail("DATE", reason);
      }
      table.daily_.push_back(row);
    } else if (type == "PRM") {
      if (table.daily_.empty()) at.fail("DATE", "a monthly row before any daily row");
      if (day_of_month != 1) at.fail("DATE", "a monthly row not dated the 1st");
      const std::int64_t expected = table.monthly_.empty() ? next_month(table.daily_.back().day)
                                                           : next_month(table.monthly_.back().day);
      if (day != expected)
        at.fail("DATE", std::string(field(col_date)).append(" does not follow the previous month"));
      table.monthly_.push_back(row);
    } else {
      at.fail("F10.7_DATA_TYPE", std::string("'").append(type).append("' is not OBS, INT, PRD or PRM"));
    }
  }
  if (table.daily_.empty()) {
    at.line = 0;
    throw std::runtime_error(name + ": no daily rows");
  }
  const std::size_t n = std::min(kPredictedApDays, table.daily_.size());
  double sum = 0.0;
  for (std::size_t i = table.daily_.size() - n; i < table.daily_.size(); ++i) sum += table.daily_[i].ap;
  table.predicted_ap_ = sum / static_cast<double>(n);
  for (Row& m : table.monthly_) m.ap = table.predicted_ap_;
  Sha256 h;
  h.update(csv);
  table.digest_ = h.hex_digest();
  return table;
}

SpaceWeather SpaceWeather::load(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  if (!file) throw std::runtime_error("space weather: cannot read " + path);
  std::stringstream buffer;
  buffer << file.rdbuf();
  const std::size_t slash = path.find_last_of('/');
  return parse(buffer.str(), slash == std::string::npos ? path : path.substr(slash + 1));
}

std::shared_ptr<const SpaceWeather> SpaceWeather::bundled() {
  return in_datasets(default_datasets_dir());
}

std::shared_ptr<const SpaceWeather> SpaceWeather::in_datasets(const std::string& datasets_dir) {
  static std::mutex mutex;
  static std::map<std::string, std::shared_ptr<const SpaceWeather>> tables;
  const std::lock_guard<std::mutex> lock(mutex);
  auto& table = tables[datasets_dir];
  if (!table) table = std::make_shared<const SpaceWeather>(load(datasets_dir + "/space_weather/SW-All.csv"));
  return table;
}

SpaceWeather::Row SpaceWeather::row_at(std::int64_t day) const {
  if (day <= last_daily_day()) return daily_[static_cast<std::size_t>(day - first_day_)];
  // Between the last daily row and the monthly rows, or between monthly rows: linear in time.
  Row before = daily_.back();
  for (const Row& after : monthly_) {
    if (day <= after.day) {
      const double w = static_cast<double>(day - before.day) / static_cast<double>(after.day - before.day);
      return {day, before.f107 + w * (after.f107 - before.f107),
              before.f107_avg + w * (after.f107_avg - before.f107_avg), predicted_ap_};
    }
    before = after;
  }
  return before;  // not reached inside [first_day, last_day]
}

DailySolarActivity SpaceWeather::observed(std::int64_t day) const {
  if (day - 1 < first_day_ || day > last_day()) return cycle(day);
  const Row today = row_at(day);
  return {row_at(day - 1).f107, today.f107_avg, today.ap};
}

DailySolarActivity SpaceWeather::cycle(std::int64_t day) const {
  const std::int64_t start = day_number(kCycleStart[0], kCycleStart[1], kCycleStart[2]);
  const std::int64_t end = day_number(kCycleEnd[0], kCycleEnd[1], kCycleEnd[2]);
  if (start - 1 < first_day_ || end - 1 > last_daily_day())
    throw std::out_of_range("space weather: the cycle mode needs daily rows from 1996-07-31 to 2019-11-30");
  const std::int64_t period = end - start;  // 8522 days
  std::int64_t offset = (day - end) % period;
  if (offset < 0) offset += period;
  const std::int64_t mapped = start + offset;
  const Row today = daily_[static_cast<std::size_t>(mapped - first_day_)];
  return {daily_[static_cast<std::size_t>(mapped - 1 - first_day_)].f107, today.f107_avg, today.ap};
}

DailySolarActivity SpaceWeather::on_day(std::int64_t day, const SolarActivitySettings& s) const {
  switch (s.mode) {
    case SolarActivityMode::kConstant:
      return {s.f107_sfu, s.f107_sfu, s.ap};
    case SolarActivityMode::kCycle:
      return cycle(day);
    case SolarActivityMode::kObserved:
    default:
      return observed(day);
  }
}

}  // namespace kessler
