#include "core/physics/msis_grid.hpp"

#include <algorithm>
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

// The sub-lattice where the full model is evaluated (build_day): every 3rd altitude node, every latitude
// node, every 2nd local-time node. Measured one axis at a time, a latitude stride of 2 would add most
// error (0.64 -> 0.82 % in the storm case), a local-time stride of 2 least (no change above 0.03 %).
constexpr int kStrideU = 3, kStrideT = 2;
constexpr int kCoarseU = (kNu - 1) / kStrideU + 1;
constexpr int kQuarterT = kTimeCells / 4;  // local-time nodes in a quarter of the diamond angle
static_assert((kNu - 1) % kStrideU == 0 && kQuarterT % kStrideT == 0);
static_assert(kCoarseU >= 4 && kQuarterT / kStrideT >= 3);

struct UtSamples {
  double sun_ra[kUtSamples] = {}, gmst[kUtSamples] = {};
};

std::size_t node_index(int iq, int it, int iu) {
  return (static_cast<std::size_t>(iq) * kNt + static_cast<std::size_t>(it)) * kNu +
         static_cast<std::size_t>(iu);
}

// Cubic Lagrange weights for fine node i of a piece [lo, hi] whose coarse nodes are lo, lo + stride, ...,
// hi: the four coarse nodes from `first` (a fine index) around i, shifted inwards at the piece's ends.
struct Stencil {
  int first = 0;
  double w[4] = {};
};

Stencil cubic_stencil(int i, int lo, int hi, int stride) {
  const int intervals = (hi - lo) / stride;
  const int j = (i - lo) / stride;
  const int first = std::clamp(j - 1, 0, intervals - 3);
  const double t = static_cast<double>(i - lo) / stride - first;
  Stencil s;
  s.first = lo + first * stride;
  s.w[0] = -(t - 1.0) * (t - 2.0) * (t - 3.0) / 6.0;
  s.w[1] = t * (t - 2.0) * (t - 3.0) / 2.0;
  s.w[2] = -t * (t - 1.0) * (t - 3.0) / 2.0;
  s.w[3] = t * (t - 1.0) * (t - 2.0) / 6.0;
  return s;
}

// One coarse column (iq, it): the full model at its coarse altitudes for each UT sample, the UT series of
// each, and the altitudes between filled along u.
void build_column(int iq, int it, int doy, const DailySolarActivity& solar, const UtSamples& ut,
                  float* coefficients) {
  const double hour_angle = MsisDensityGrid::node_hour_angle_rad(it);
  double lst = 12.0 + hour_angle * 12.0 / kPi;
  lst = lst < 0.0 ? lst + 24.0 : lst;
  const nrlmsise00::Switches switches = nrlmsise00::Switches::all_on();
  double samples[kUtSamples][kCoarseU];
  for (int k = 0; k < kUtSamples; ++k) {
    MsisInput in;
    in.day_of_year = doy;
    in.ut_s = k * kDay_s / kUtSamples;
    in.latitude_deg = MsisDensityGrid::node_latitude_deg(iq);
    in.local_solar_time_h = lst;
    in.longitude_deg = wrap_degrees((ut.sun_ra[k] + hour_angle - ut.gmst[k]) * 180.0 / kPi);
    in.f107 = solar.f107;
    in.f107_avg = solar.f107_avg;
    in.ap = solar.ap;
    in.altitude_km = 400.0;  // the column's terms do not depend on it
    const nrlmsise00::ColumnTerms terms(in, switches);
    for (int c = 0; c < kCoarseU; ++c)
      samples[k][c] = std::log(terms.at(MsisDensityGrid::node_altitude_km(c * kStrideU)).rho_drag_kg_m3);
  }
  double series[kCoarseU][kCoefficients] = {};
  for (std::size_t c = 0; c < kCoarseU; ++c) {
    for (int k = 0; k < kUtSamples; ++k) {
      const double v = samples[k][c];
      series[c][0] += v / kUtSamples;
      for (int m = 1; m <= kUtHarmonics; ++m) {
        const double angle = 2.0 * kPi * m * k / kUtSamples;
        series[c][2 * static_cast<std::size_t>(m) - 1] += 2.0 * v * std::cos(angle) / kUtSamples;
        series[c][2 * static_cast<std::size_t>(m)] += 2.0 * v * std::sin(angle) / kUtSamples;
      }
    }
  }
  for (int iu = 0; iu < kNu; ++iu) {
    const std::size_t node = node_index(iq, it, iu);
    if (iu % kStrideU == 0) {
      for (int j = 0; j < kCoefficients; ++j)
        coefficients[j * kNodes + node] = static_cast<float>(series[iu / kStrideU][j]);
      continue;
    }
    const Stencil s = cubic_stencil(iu, 0, kNu - 1, kStrideU);
    for (int j = 0; j < kCoefficients; ++j) {
      double v = 0.0;
      for (int k = 0; k < 4; ++k) v += s.w[k] * series[s.first / kStrideU + k][j];
      coefficients[j * kNodes + node] = static_cast<float>(v);
    }
  }
}

// Fine node `to` = sum of w[k] times the nodes from[k], for every coefficient.
void combine(float* coefficients, std::size_t to, const std::size_t (&from)[4], const double (&w)[4]) {
  for (int j = 0; j < kCoefficients; ++j) {
    const float* c = coefficients + static_cast<std::size_t>(j) * kNodes;
    const double v = w[0] * c[from[0]] + w[1] * c[from[1]] + w[2] * c[from[2]] + w[3] * c[from[3]];
    coefficients[static_cast<std::size_t>(j) * kNodes + to] = static_cast<float>(v);
  }
}

// The local times between coarse ones; then the repeated node at local noon.
void fill_local_times(float* coefficients) {
#pragma omp parallel for schedule(static)
  for (int iq = 0; iq < kNq; ++iq) {
    for (int it = 0; it < kTimeCells; ++it) {
      if (it % kStrideT == 0) continue;
      const int lo = it / kQuarterT * kQuarterT;
      const Stencil s = cubic_stencil(it, lo, lo + kQuarterT, kStrideT);
      for (int iu = 0; iu < kNu; ++iu) {
        std::size_t from[4];
        for (int k = 0; k < 4; ++k) from[k] = node_index(iq, (s.first + k * kStrideT) % kTimeCells, iu);
        combine(coefficients, node_index(iq, it, iu), from, s.w);
      }
    }
    for (int iu = 0; iu < kNu; ++iu)
      for (int j = 0; j < kCoefficients; ++j)
        coefficients[j * kNodes + node_index(iq, kTimeCells, iu)] =
            coefficients[j * kNodes + node_index(iq, 0, iu)];
  }
}

}  // namespace

MsisDensityGrid::MsisDensityGrid(const UtcEpoch& epoch, const SolarActivitySettings& settings,
                                 std::shared_ptr<const SpaceWeather> space_weather)
    : epoch_(epoch), settings_(settings), space_weather_(std::move(space_weather)) {
  if (settings_.mode != SolarActivityMode::kConstant) {
    if (!space_weather_)
      throw std::invalid_argument("NRLMSISE-00: solar activity needs a space weather table");
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
  const DailySolarActivity solar =
      space_weather_ ? space_weather_->on_day(day, settings_)
                     : DailySolarActivity{settings_.f107_sfu, settings_.f107_sfu, settings_.ap};
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

// The full model is evaluated on a sub-lattice (kStrideU, kStrideT) and the nodes between are filled by
// cubic Lagrange interpolation, along u within each column, then along the local-time pseudo-angle p.
// Local-time stencils stay inside one quarter of the diamond angle (noon to 18 h, ...), where its map to
// the hour angle is smooth. ln rho is smooth along both, so the filled nodes add little to the force
// model's own (trilinear) error; the test bounds the sum.
MsisDensityGrid::Day MsisDensityGrid::build_day(std::int64_t day) const {
  Day out;
  out.day = day;
  out.coefficients.assign(kNodes * kCoefficients, 0.0f);
  const DailySolarActivity solar =
      space_weather_ ? space_weather_->on_day(day, settings_)
                     : DailySolarActivity{settings_.f107_sfu, settings_.f107_sfu, settings_.ap};
  const int doy = day_of_year(day);
  const UtcEpoch midnight = UtcEpoch::from_julian_date(2440587.5 + static_cast<double>(day), 0.0);
  UtSamples ut;
  for (int k = 0; k < kUtSamples; ++k) {
    const UtcEpoch when = midnight.plus_seconds(k * kDay_s / kUtSamples);
    ut.sun_ra[k] = sun_right_ascension(when);
    ut.gmst[k] = when.gmst_rad();
  }
  float* coefficients = out.coefficients.data();
  constexpr int kCoarseT = kTimeCells / kStrideT;
#pragma omp parallel for schedule(dynamic, 2)
  for (int column = 0; column < kNq * kCoarseT; ++column)
    build_column(column / kCoarseT, column % kCoarseT * kStrideT, doy, solar, ut, coefficients);
  fill_local_times(coefficients);
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
