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

// The build's sample lattice (build_day). Latitude: Chebyshev-Lobatto points (polynomial interpolation
// to the nodes; the model's latitude terms are Legendre functions, smooth up to the poles). Local time:
// equally spaced hour angles (trigonometric interpolation; the model's terms are harmonics of it).
// Altitude: every 3rd node below 120 km, every node to 167 km (ln n bends most above the 120 km
// boundary), every 5th above, and the nodes either side of each species' switch altitude (kBreaks).
constexpr int kLatSamples = 23;
constexpr int kTimeSamples = 15;  // odd: no unpaired Nyquist term
constexpr int kBelow120 = 13;     // the last altitude node below 120 km
constexpr int kDenseTop = 22;     // every node to here (167 km)
constexpr int kStrideLow = 3, kStrideHigh = 5;
constexpr int kSpecies = 8;  // He, O, N2, O2, Ar, H, N, anomalous O (MsisOutput's order)
constexpr double kMass[kSpecies] = {4.0, 16.0, 28.0, 32.0, 40.0, 1.0, 14.0, 16.0};
constexpr double kAmu_kg = 1.66e-27;  // the model's atomic mass unit
// Altitudes [km] where the model switches a species' mixing corrections on or off (and, at 120 km, the
// exospheric temperature it uses): each species' ln n is smooth only between them, so its altitude
// stencils stay within (0: none).
constexpr double kBreaks[kSpecies][3] = {{120, 200, 0}, {120, 300, 0},   {120, 160, 0},   {120, 250, 0},
                                         {120, 240, 0}, {120, 300, 320}, {120, 300, 450}, {120, 0, 0}};
constexpr int kRow = kCoefficients * kNu;  // one sample column's UT series, [j][iu]

// Weights that depend on the layout alone (computed once).
struct Plan {
  std::vector<int> coarse;   // altitude nodes where the model is evaluated
  std::vector<int> between;  // the others, ascending
  // Per species and `between` node: 4 positions in `coarse` and their cubic (or lower, padded with
  // zero weights) Lagrange weights in u.
  std::vector<int> idx;  // [kSpecies][kNu][4]
  std::vector<double> w;
  double lat_deg[kLatSamples] = {}, hour_angle[kTimeSamples] = {};
  std::vector<double> lat_w;   // [kNq][kLatSamples]
  std::vector<double> time_w;  // [kTimeCells][kTimeSamples]
};

double u_of_km(double km) {
  return std::sqrt(km - kBase_km) / kStepU;
}

// Lagrange weights at fine node iu for species sp, from the coarse nodes in its segment nearest iu.
void altitude_stencil(Plan& p, int sp, int iu, int f) {
  auto segment = [&](int i) {
    int k = 0;
    for (double km : kBreaks[sp]) k += km > 0.0 && u_of_km(km) < i;
    return k;
  };
  std::vector<int> same;  // positions in p.coarse
  for (std::size_t c = 0; c < p.coarse.size(); ++c)
    if (segment(p.coarse[c]) == segment(iu)) same.push_back(static_cast<int>(c));
  const int size = static_cast<int>(same.size());
  const int n = std::min(4, size);
  int j = 0;
  while (j + 1 < size && p.coarse[same[j + 1]] <= iu) ++j;
  const int first = std::clamp(j - 1, 0, size - n);
  const std::size_t at = (static_cast<std::size_t>(sp) * kNu + f) * 4;
  for (int k = 0; k < 4; ++k) {
    p.idx[at + k] = same[first + (k < n ? k : 0)];
    double w = k < n ? 1.0 : 0.0;
    for (int l = 0; l < n && k < n; ++l)
      if (l != k)
        w *= (iu - p.coarse[same[first + l]]) /
             static_cast<double>(p.coarse[same[first + k]] - p.coarse[same[first + l]]);
    p.w[at + k] = w;
  }
}

void altitude_plan(Plan& p) {
  std::vector<char> coarse(kNu, 0);
  for (int i = 0; i < kNu - 1; i += i < kBelow120 ? kStrideLow : i < kDenseTop ? 1 : kStrideHigh)
    coarse[i] = 1;
  coarse[kNu - 1] = 1;
  for (const auto& breaks : kBreaks)
    for (double km : breaks)
      if (km > 0.0) coarse[static_cast<int>(u_of_km(km))] = coarse[static_cast<int>(u_of_km(km)) + 1] = 1;
  for (int i = 0; i < kNu; ++i) (coarse[i] ? p.coarse : p.between).push_back(i);
  p.idx.assign(static_cast<std::size_t>(kSpecies) * kNu * 4, 0);
  p.w.assign(p.idx.size(), 0.0);
  for (int sp = 0; sp < kSpecies; ++sp)
    for (std::size_t f = 0; f < p.between.size(); ++f)
      altitude_stencil(p, sp, p.between[f], static_cast<int>(f));
}

void latitude_plan(Plan& p) {
  for (int a = 0; a < kLatSamples; ++a) p.lat_deg[a] = -90.0 * std::cos(kPi * a / (kLatSamples - 1));
  p.lat_w.assign(static_cast<std::size_t>(kNq) * kLatSamples, 0.0);
  for (int iq = 0; iq < kNq; ++iq) {
    const double x = MsisDensityGrid::node_latitude_deg(iq);
    double* w = &p.lat_w[static_cast<std::size_t>(iq) * kLatSamples];
    const double* hit = std::find(p.lat_deg, p.lat_deg + kLatSamples, x);
    if (hit != p.lat_deg + kLatSamples) {
      w[hit - p.lat_deg] = 1.0;
      continue;
    }
    double sum = 0.0;  // barycentric form
    for (int a = 0; a < kLatSamples; ++a) {
      w[a] = (a % 2 ? -1.0 : 1.0) * (a == 0 || a == kLatSamples - 1 ? 0.5 : 1.0) / (x - p.lat_deg[a]);
      sum += w[a];
    }
    for (int a = 0; a < kLatSamples; ++a) w[a] /= sum;
  }
}

void time_plan(Plan& p) {
  for (int b = 0; b < kTimeSamples; ++b) p.hour_angle[b] = 2.0 * kPi * b / kTimeSamples;
  p.time_w.assign(static_cast<std::size_t>(kTimeCells) * kTimeSamples, 0.0);
  for (int it = 0; it < kTimeCells; ++it) {
    const double x = MsisDensityGrid::node_hour_angle_rad(it);
    for (int b = 0; b < kTimeSamples; ++b) {
      double w = 1.0;  // the Dirichlet kernel
      for (int m = 1; m <= kTimeSamples / 2; ++m) w += 2.0 * std::cos(m * (x - p.hour_angle[b]));
      p.time_w[static_cast<std::size_t>(it) * kTimeSamples + b] = w / kTimeSamples;
    }
  }
}

const Plan& plan() {
  static const Plan p = [] {
    Plan q;
    altitude_plan(q);
    latitude_plan(q);
    time_plan(q);
    return q;
  }();
  return p;
}

struct UtSamples {
  double sun_ra[kUtSamples] = {}, gmst[kUtSamples] = {};
};

std::size_t node_index(int iq, int it, int iu) {
  return (static_cast<std::size_t>(iq) * kNt + static_cast<std::size_t>(it)) * kNu +
         static_cast<std::size_t>(iu);
}

// Four-point stencil f of species sp applied to values v (by position in plan().coarse).
double stencil(const Plan& p, int sp, int f, const double* v) {
  const std::size_t at = (static_cast<std::size_t>(sp) * kNu + f) * 4;
  const int* i = &p.idx[at];
  const double* w = &p.w[at];
  return w[0] * v[i[0]] + w[1] * v[i[1]] + w[2] * v[i[2]] + w[3] * v[i[3]];
}

// ln rho at every altitude node of a column: the model at the coarse nodes; between them, above 120 km,
// each species' ln n interpolated and the mass density summed (the sum of species with different scale
// heights bends ln rho, most where He gives way to H, which a stencil in ln rho itself smooths over);
// below 120 km ln rho itself (anomalous oxygen's ln n is not smooth there, and nothing else switches).
void column_profile(const nrlmsise00::ColumnTerms& terms, const Plan& p, double* ln_rho) {
  const int nc = static_cast<int>(p.coarse.size()), nb = static_cast<int>(p.between.size());
  double ln_n[kSpecies][kNu], ln_r[kNu];
  for (int c = 0; c < nc; ++c) {
    const MsisOutput o = terms.at(MsisDensityGrid::node_altitude_km(p.coarse[c]));
    ln_r[c] = std::log(o.rho_drag_kg_m3);
    ln_rho[p.coarse[c]] = ln_r[c];
    const double n[kSpecies] = {o.he, o.o, o.n2, o.o2, o.ar, o.h, o.n, o.anomalous_o};
    for (int sp = 0; sp < kSpecies; ++sp) ln_n[sp][c] = std::log(std::max(n[sp], 1.0e-300));
  }
  double rho[kNu] = {}, v[kNu];
  for (int sp = 0; sp < kSpecies; ++sp) {
    for (int f = 0; f < nb; ++f) v[f] = stencil(p, sp, f, ln_n[sp]);
    for (int f = 0; f < nb; ++f) rho[f] += kMass[sp] * deterministic_exp(v[f]);
  }
  for (int f = 0; f < nb; ++f)
    ln_rho[p.between[f]] = p.between[f] <= kBelow120 ? stencil(p, kSpecies - 1, f, ln_r)  // only 120 km
                                                     : std::log(kAmu_kg * rho[f]);
}

// Sample column (a, b): the model at each UT sample, then its UT series, to series[j * kNu + iu].
void sample_column(int a, int b, int doy, const DailySolarActivity& solar, const UtSamples& ut,
                   double* series) {
  const Plan& p = plan();
  const double hour_angle = p.hour_angle[b];
  const double lst = 12.0 + hour_angle * 12.0 / kPi;
  const nrlmsise00::Switches switches = nrlmsise00::Switches::all_on();
  double samples[kUtSamples][kNu];
  for (int k = 0; k < kUtSamples; ++k) {
    MsisInput in;
    in.day_of_year = doy;
    in.ut_s = k * kDay_s / kUtSamples;
    in.latitude_deg = p.lat_deg[a];
    in.local_solar_time_h = lst >= 24.0 ? lst - 24.0 : lst;
    in.longitude_deg = wrap_degrees((ut.sun_ra[k] + hour_angle - ut.gmst[k]) * 180.0 / kPi);
    in.f107 = solar.f107;
    in.f107_avg = solar.f107_avg;
    in.ap = solar.ap;
    in.altitude_km = 400.0;  // the column's terms do not depend on it
    column_profile(nrlmsise00::ColumnTerms(in, switches), p, samples[k]);
  }
  std::fill(series, series + kRow, 0.0);
  for (int k = 0; k < kUtSamples; ++k) {
    double w[kCoefficients] = {1.0 / kUtSamples};
    for (std::size_t m = 1; m <= kUtHarmonics; ++m) {
      const double angle = 2.0 * kPi * static_cast<double>(m) * k / kUtSamples;
      w[2 * m - 1] = 2.0 * std::cos(angle) / kUtSamples;
      w[2 * m] = 2.0 * std::sin(angle) / kUtSamples;
    }
    for (int j = 0; j < kCoefficients; ++j)
      for (int iu = 0; iu < kNu; ++iu) series[j * kNu + iu] += w[j] * samples[k][iu];
  }
}

// Latitude node iq: the samples' series interpolated to its latitude, then to each local-time node.
void expand_latitude(int iq, const std::vector<double>& series, float* coefficients) {
  const Plan& p = plan();
  std::vector<double> at_lat(static_cast<std::size_t>(kTimeSamples) * kRow, 0.0);
  const double* wq = &p.lat_w[static_cast<std::size_t>(iq) * kLatSamples];
  for (int b = 0; b < kTimeSamples; ++b) {
    double* out = &at_lat[static_cast<std::size_t>(b) * kRow];
    for (int a = 0; a < kLatSamples; ++a) {
      const double* in = &series[(static_cast<std::size_t>(a) * kTimeSamples + b) * kRow];
      for (int i = 0; i < kRow; ++i) out[i] += wq[a] * in[i];
    }
  }
  double row[kRow];
  for (int it = 0; it < kTimeCells; ++it) {
    const double* wt = &p.time_w[static_cast<std::size_t>(it) * kTimeSamples];
    std::fill(row, row + kRow, 0.0);
    for (int b = 0; b < kTimeSamples; ++b) {
      const double* in = &at_lat[static_cast<std::size_t>(b) * kRow];
      for (int i = 0; i < kRow; ++i) row[i] += wt[b] * in[i];
    }
    for (int j = 0; j < kCoefficients; ++j) {
      float* to = coefficients + j * kNodes + node_index(iq, it, 0);
      float* noon = coefficients + j * kNodes + node_index(iq, kTimeCells, 0);  // repeats it = 0
      for (int iu = 0; iu < kNu; ++iu) {
        to[iu] = static_cast<float>(row[j * kNu + iu]);
        if (it == 0) noon[iu] = to[iu];
      }
    }
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

// The full model on the sample lattice (plan()): per sample column and UT sample one ColumnTerms and
// the coarse altitudes, filled along altitude (column_profile), reduced to the UT series, then
// interpolated to the nodes along latitude and local time (expand_latitude). Each output value is the
// same sum in the same order whichever thread computes it.
MsisDensityGrid::Day MsisDensityGrid::build_day(std::int64_t day) const {
  Day out;
  out.day = day;
  out.coefficients.resize(kNodes * kCoefficients);  // every element written below
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
  plan();  // built once, before the threads
  constexpr int kColumns = kLatSamples * kTimeSamples;
  std::vector<double> series(static_cast<std::size_t>(kColumns) * kRow);
#pragma omp parallel for schedule(dynamic, 1)
  for (int column = 0; column < kColumns; ++column)
    sample_column(column / kTimeSamples, column % kTimeSamples, doy, solar, ut,
                  &series[static_cast<std::size_t>(column) * kRow]);
  float* coefficients = out.coefficients.data();
#pragma omp parallel for schedule(dynamic, 1)
  for (int iq = 0; iq < kNq; ++iq) expand_latitude(iq, series, coefficients);
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
