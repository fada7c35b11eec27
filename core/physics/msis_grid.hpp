// NRLMSISE-00 for the force model: the full model costs ~9 us a point, far too much per object and force
// evaluation, so the force model reads a precomputed grid of ln rho (the drag density, with anomalous
// oxygen) instead. Everything in the grid comes from the time alone (and the solar-activity settings),
// never from the population or the thread layout, so runs stay deterministic for any thread count.
//
// Grid coordinates (all from the position in TEME, no trigonometry per object):
//  - altitude h = |r| - R_eq (a sphere, as for the table), through u = sqrt(h - 90 km) in steps of 0.4
//    sqrt(km): 124 nodes from 90 to 2511 km, 6 km apart at 150 km, 40 km at 2500 km (ln rho bends most
//    low down); below 90 km the 90 km value, above the top the last cell's slope continues;
//  - latitude (geocentric) through the pseudo-angle q = z / (sqrt(x^2 + y^2) + |z|) in [-1, 1], monotone
//    in latitude: 64 cells, at most 3.6 deg wide;
//  - local solar time through the pseudo-angle of the position's direction in the equatorial plane
//    relative to the Sun's (along = r . s, across = r x s, diamond angle in [0, 4), 0 at local noon):
//    80 cells, at most 0.4 h wide.
// ln rho is interpolated trilinearly in (u, q, p) and rho = exp of it (deterministic_exp).
//
// Time: the model's solar inputs, day of year and UT terms. For each UTC day the grid's nodes are
// evaluated at 7 UT samples (the day's solar inputs, SpaceWeather) and stored as a trigonometric series
// in UT (mean and 3 harmonics: the model's UT and longitude terms are harmonics of UT at fixed latitude
// and local time). The grid a force evaluation reads is the series at the middle of its 120 s slot of
// UTC. The model's own day-to-day jumps (daily F10.7, Ap, day of year) stay at midnight UTC.
//
// Building a day: the full model on a sample lattice, not at the nodes: 23 latitudes (Chebyshev-Lobatto,
// polynomial interpolation to the nodes), 15 hour angles (equally spaced, trigonometric interpolation),
// 7 UT samples (7 x 345 columns' expansions, nrlmsise00::ColumnTerms) and 42 altitudes a column (101,000
// profiles); between those altitudes each species' ln n is interpolated and the densities summed, never
// across the altitudes where the model switches a species' corrections (msis_grid.cpp). Shared out
// between OpenMP threads; a slot, one pass over the nodes.
//
// Measured interpolation error against the full model: tests/atmosphere/msis_grid_test.cpp and
// core/physics/README.md.
#pragma once

#include <cmath>
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <vector>

#include <Eigen/Core>

#include "core/physics/deterministic_exp.hpp"
#include "core/physics/nrlmsise00/nrlmsise00.hpp"
#include "core/physics/space_weather.hpp"
#include "core/time/epoch.hpp"

namespace kessler {

namespace msis_grid {
inline constexpr double kBase_km = 90.0;
inline constexpr double kStepU = 0.4;  // sqrt(km)
inline constexpr int kAltitudeCells = 123;
inline constexpr int kLatitudeCells = 64;
inline constexpr int kTimeCells = 80;
inline constexpr int kNu = kAltitudeCells + 1;
inline constexpr int kNt = kTimeCells + 1;  // the last node repeats the first (local noon)
inline constexpr int kNq = kLatitudeCells + 1;
inline constexpr std::size_t kNodes = static_cast<std::size_t>(kNu) * kNt * kNq;
inline constexpr double kSlot_s = 120.0;
inline constexpr int kUtHarmonics = 3;
inline constexpr int kUtSamples = 2 * kUtHarmonics + 1;
}  // namespace msis_grid

// Density [kg/m^3] from a slot's grid at TEME position (x, y, z) [m] with altitude |r| - R_eq [m]; (sun_x,
// sun_y) the Sun's direction in the equatorial plane (unit). Only + - * / sqrt and deterministic_exp.
[[gnu::always_inline]] inline double msis_grid_density(const float* grid, double sun_x, double sun_y,
                                                       double x, double y, double z, double altitude_m) {
  using namespace msis_grid;
  double hk = altitude_m * 1.0e-3 - kBase_km;
  hk = hk > 0.0 ? hk : 0.0;  // also NaN -> 0
  const double u = std::sqrt(hk) * (1.0 / kStepU);
  const double u_cell = u < kAltitudeCells - 1.0 ? u : kAltitudeCells - 1.0;
  const int iu = static_cast<int>(u_cell);
  const double fu = u - iu;  // > 1 above the top: the last cell's slope continues
  const double rxy = std::sqrt(x * x + y * y);
  double vq = (z / (rxy + std::fabs(z) + 1.0e-30) + 1.0) * (0.5 * kLatitudeCells);
  vq = vq > 0.0 ? vq : 0.0;
  vq = vq < kLatitudeCells - 1.0e-9 ? vq : kLatitudeCells - 1.0e-9;
  const int iq = static_cast<int>(vq);
  const double fq = vq - iq;
  const double along = x * sun_x + y * sun_y;
  const double across = y * sun_x - x * sun_y;
  const double inv_d = 1.0 / (std::fabs(along) + std::fabs(across) + 1.0e-30);
  const double a = along * inv_d;
  double p = across >= 0.0 ? 1.0 - a : 3.0 + a;  // [0, 4], 0 at local noon
  double vt = p * (0.25 * kTimeCells);
  vt = vt > 0.0 ? vt : 0.0;
  vt = vt < kTimeCells - 1.0e-9 ? vt : kTimeCells - 1.0e-9;
  const int it = static_cast<int>(vt);
  const double ft = vt - it;
  // Indices as int, read as grid[i]: the form GCC turns into vector gathers.
  constexpr int kT = kNu, kQ = kNu * kNt;
  const int i = (iq * kNt + it) * kNu + iu;
  const double g000 = grid[i], g001 = grid[i + 1], g010 = grid[i + kT], g011 = grid[i + kT + 1];
  const double g100 = grid[i + kQ], g101 = grid[i + kQ + 1], g110 = grid[i + kQ + kT],
               g111 = grid[i + kQ + kT + 1];
  const double c00 = g000 + fu * (g001 - g000);
  const double c01 = g010 + fu * (g011 - g010);
  const double c10 = g100 + fu * (g101 - g100);
  const double c11 = g110 + fu * (g111 - g110);
  const double c0 = c00 + ft * (c01 - c00);
  const double c1 = c10 + ft * (c11 - c10);
  return deterministic_exp(c0 + fq * (c1 - c0));
}

class MsisDensityGrid {
 public:
  MsisDensityGrid(const UtcEpoch& epoch, const SolarActivitySettings& settings,
                  std::shared_ptr<const SpaceWeather> space_weather);

  // The grid of the 60 s slot holding t_s (seconds since the epoch); kept alive by the pointer.
  std::shared_ptr<const float[]> grid_at(double t_s);

  // The full model where the grid stands for a TEME position at t_s: geocentric latitude, altitude
  // |r| - R_eq, local solar time from the Sun's right ascension, longitude from GMST, the day's inputs.
  MsisInput model_input(double t_s, const Eigen::Vector3d& r_m) const;
  // The Sun's direction in the equatorial plane at t_s (unit), as the force model passes it.
  Eigen::Vector2d sun_direction(double t_s) const;

  const SolarActivitySettings& settings() const { return settings_; }

  // Node coordinates.
  static double node_altitude_km(int iu);
  static double node_latitude_deg(int iq);
  static double node_hour_angle_rad(int it);  // local solar time = 12 h + this (in hours) / (pi/12)

 private:
  struct Day {
    std::int64_t day = 0;
    // kUtSamples arrays of kNodes: the mean, then cos and sin of each UT harmonic (floats: ln rho to
    // ~4e-6, and half the bytes each slot reads).
    std::vector<float> coefficients;
  };
  const Day& day_coefficients(std::int64_t day);  // with mutex_ held
  Day build_day(std::int64_t day) const;

  UtcEpoch epoch_;
  SolarActivitySettings settings_;
  std::shared_ptr<const SpaceWeather> space_weather_;
  std::mutex mutex_;
  std::deque<Day> days_;                                                       // the last two days built
  std::deque<std::pair<std::int64_t, std::shared_ptr<const float[]>>> slots_;  // the last few
};

}  // namespace kessler
