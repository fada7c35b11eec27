#include "core/physics/msis_grid.hpp"

#include <numbers>
#include <stdexcept>

#include "core/physics/constants.hpp"
#include "core/physics/sun_ephemeris.hpp"

namespace kessler {
namespace {

using namespace msis_grid;
constexpr double kPi = std::numbers::pi;
constexpr double kDay_s = 86400.0;
constexpr std::size_t kSlotsKept = 4;
constexpr std::size_t kDaysKept = 2;
constexpr int kCoefficients = kUtSamples;  // mean, then cos and sin of each harmonic

// Day of year (1..366) of a UTC day number.
int day_of_year(std::int64_t day) {
  const UtcEpoch e = UtcEpoch::from_julian_date(2440587.5 + static_cast<double>(day), 0.0);
  int y, mo, d, h, mi;
  double s;
  e.to_calendar(y, mo, d, h, mi, s);
  return static_cast<int>(day_number(y, mo, d) - day_number(y, 1, 1)) + 1;
}

double wrap_degrees(double deg) {
  deg = std::fmod(deg, 360.0);
  if (deg >= 180.0) deg -= 360.0;
  if (deg < -180.0) deg += 360.0;
  return deg;
}

double sun_right_ascension(const UtcEpoch& when) {
  const Eigen::Vector3d sun = sun_position_m(when);
  return std::atan2(sun.y(), sun.x());
}

}  // namespace

MsisDensityGrid::MsisDensityGrid(const UtcEpoch& epoch, const SolarActivitySettings& settings,
                                 std::shared_ptr<const SpaceWeather> space_weather)
    : epoch_(epoch), settings_(settings), space_weather_(std::move(space_weather)) {
  if (settings_.mode != SolarActivityMode::kConstant) {
    if (!space_weather_) throw std::invalid_argument("NRLMSISE-00: solar activity needs a space weather table");
    space_weather_->cycle(day_number(epoch));  // throws when the table lacks cycles 23-24
  } else if (!(settings_.f107_sfu > 0.0) || !(settings_.ap >= 0.0)) {
    throw std::invalid_argument("NRLMSISE-00: constant solar activity needs f107 > 0 and ap >= 0");
  }
}

double MsisDensityGrid::node_altitude_km(int iu) {
  const double u = iu * kStepU;
  return kBase_km + u * u;
}

double MsisDensityGrid::node_latitude_deg(int iq) {
  const double q = -1.0 + 2.0 * iq / kLatitudeCells;  // q = tan(lat) / (1 + |tan(lat)|)
  if (q >= 1.0) return 90.0;
  if (q <= -1.0) return -90.0;
  return std::atan(q / (1.0 - std::fabs(q))) * 180.0 / kPi;
}

double MsisDensityGrid::node_hour_angle_rad(int it) {
  // The diamond angle p in [0, 4] back to a direction (a, c) on |a| + |c| = 1, then its angle.
  const double p = 4.0 * it / kTimeCells;
  double a, c;
  if (p <= 1.0) {
    a = 1.0 - p, c = p;
  } else if (p <= 2.0) {
    a = 1.0 - p, c = 2.0 - p;
  } else if (p <= 3.0) {
    a = p - 3.0, c = 2.0 - p;
  } else {
    a = p - 3.0, c = p - 4.0;
  }
  return std::atan2(c, a);
}

Eigen::Vector2d MsisDensityGrid::sun_direction(double t_s) const {
  const Eigen::Vector3d sun = sun_position_m(epoch_.plus_seconds(t_s));
  return Eigen::Vector2d(sun.x(), sun.y()).normalized();
}

MsisInput MsisDensityGrid::model_input(double t_s, const Eigen::Vector3d& r) const {
  const UtcEpoch when = epoch_.plus_seconds(t_s);
  const std::int64_t day = day_number(when);
  const DailySolarActivity solar = space_weather_ ? space_weather_->on_day(day, settings_)
                                                  : DailySolarActivity{settings_.f107_sfu, settings_.f107_sfu,
                                                                       settings_.ap};
  MsisInput in;
  in.day_of_year = day_of_year(day);
  in.ut_s = when.jd_fraction() * kDay_s;
  in.altitude_km = (r.norm() - constants::kEarthEquatorialRadius_m) * 1.0e-3;
  in.latitude_deg = std::asin(r.z() / r.norm()) * 180.0 / kPi;
  const double ra = std::atan2(r.y(), r.x());
  const double hour_angle = ra - sun_right_ascension(when);
  double lst = 12.0 + hour_angle * 12.0 / kPi;
  lst = std::fmod(lst, 24.0);
  in.local_solar_time_h = lst < 0.0 ? lst + 24.0 : lst;
  in.longitude_deg = wrap_degrees((ra - when.gmst_rad()) * 180.0 / kPi);
  in.f107 = solar.f107;
  in.f107_avg = solar.f107_avg;
  in.ap = solar.ap;
  return in;
}

MsisDensityGrid::Day MsisDensityGrid::build_day(std::int64_t day) const {
  Day out;
  out.day = day;
  out.coefficients.assign(kNodes * kCoefficients, 0.0f);
  const DailySolarActivity solar = space_weather_ ? space_weather_->on_day(day, settings_)
                                                  : DailySolarActivity{settings_.f107_sfu, settings_.f107_sfu,
                                                                       settings_.ap};
  const int doy = day_of_year(day);
  const UtcEpoch midnight = UtcEpoch::from_julian_date(2440587.5 + static_cast<double>(day), 0.0);
  double sun_ra[kUtSamples], gmst[kUtSamples];
  for (int k = 0; k < kUtSamples; ++k) {
    const UtcEpoch when = midnight.plus_seconds(k * kDay_s / kUtSamples);
    sun_ra[k] = sun_right_ascension(when);
    gmst[k] = when.gmst_rad();
  }
  const nrlmsise00::Switches switches = nrlmsise00::Switches::all_on();
  float* coefficients = out.coefficients.data();
  // One column (latitude, local time) per iteration: its 5 UT samples, then each node's series.
#pragma omp parallel for schedule(dynamic, 4)
  for (int column = 0; column < kNq * kNt; ++column) {
    const int iq = column / kNt, it = column % kNt;
    const double hour_angle = node_hour_angle_rad(it % kTimeCells);
    double lst = 12.0 + hour_angle * 12.0 / kPi;
    lst = lst < 0.0 ? lst + 24.0 : lst;
    double samples[kUtSamples][kNu];
    for (int k = 0; k < kUtSamples; ++k) {
      MsisInput in;
      in.day_of_year = doy;
      in.ut_s = k * kDay_s / kUtSamples;
      in.latitude_deg = node_latitude_deg(iq);
      in.local_solar_time_h = lst;
      in.longitude_deg = wrap_degrees((sun_ra[k] + hour_angle - gmst[k]) * 180.0 / kPi);
      in.f107 = solar.f107;
      in.f107_avg = solar.f107_avg;
      in.ap = solar.ap;
      in.altitude_km = 400.0;  // the column's terms do not depend on it
      const nrlmsise00::ColumnTerms terms(in, switches);
      for (int iu = 0; iu < kNu; ++iu) samples[k][iu] = std::log(terms.at(node_altitude_km(iu)).rho_drag_kg_m3);
    }
    for (int iu = 0; iu < kNu; ++iu) {
      double c[kCoefficients] = {};
      for (int k = 0; k < kUtSamples; ++k) {
        const double v = samples[k][iu];
        c[0] += v / kUtSamples;
        for (int m = 1; m <= kUtHarmonics; ++m) {
          const double angle = 2.0 * kPi * m * k / kUtSamples;
          c[2 * static_cast<std::size_t>(m) - 1] += 2.0 * v * std::cos(angle) / kUtSamples;
          c[2 * static_cast<std::size_t>(m)] += 2.0 * v * std::sin(angle) / kUtSamples;
        }
      }
      const std::size_t node = (static_cast<std::size_t>(iq) * kNt + it) * kNu + iu;
      for (int j = 0; j < kCoefficients; ++j) coefficients[j * kNodes + node] = static_cast<float>(c[j]);
    }
  }
  return out;
}

const MsisDensityGrid::Day& MsisDensityGrid::day_coefficients(std::int64_t day) {
  for (const Day& d : days_)
    if (d.day == day) return d;
  days_.push_back(build_day(day));
  if (days_.size() > kDaysKept) days_.pop_front();
  return days_.back();
}

std::shared_ptr<const float[]> MsisDensityGrid::grid_at(double t_s) {
  const UtcEpoch when = epoch_.plus_seconds(t_s);
  const std::int64_t day = day_number(when);
  const auto slot_of_day = static_cast<std::int64_t>(std::floor(when.jd_fraction() * (kDay_s / kSlot_s)));
  const std::int64_t slot = day * static_cast<std::int64_t>(kDay_s / kSlot_s) + slot_of_day;
  std::lock_guard<std::mutex> lock(mutex_);
  for (const auto& [key, grid] : slots_)
    if (key == slot) return grid;
  const Day& d = day_coefficients(day);
  const double angle = 2.0 * kPi * (static_cast<double>(slot_of_day) + 0.5) * kSlot_s / kDay_s;
  double w[kCoefficients];
  w[0] = 1.0;
  for (int m = 1; m <= kUtHarmonics; ++m) {
    w[2 * static_cast<std::size_t>(m) - 1] = std::cos(m * angle);
    w[2 * static_cast<std::size_t>(m)] = std::sin(m * angle);
  }
  std::shared_ptr<float[]> grid(new float[kNodes]);  // every element written below
  const float* c = d.coefficients.data();
  float* __restrict g = grid.get();
  for (std::size_t n = 0; n < kNodes; ++n) {
    double sum = c[n];
    for (int j = 1; j < kCoefficients; ++j) sum += c[j * kNodes + n] * w[j];
    g[n] = static_cast<float>(sum);
  }
  slots_.emplace_back(slot, std::shared_ptr<const float[]>(std::move(grid)));
  if (slots_.size() > kSlotsKept) slots_.pop_front();
  return slots_.back().second;
}

}  // namespace kessler
