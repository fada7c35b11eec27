// Atmospheric density rho(h) [kg/m^3] at altitude h [m] above the equatorial radius (a sphere: the
// altitude the burn-up rule uses too). Two models, chosen per scenario (ForceModelSettings::atmosphere):
//
// 1. DensityTable (default): the exponential atmosphere of Vallado, "Fundamentals of Astrodynamics and
//    Applications" (4th ed.), Table 8-4 (CIRA-72 based; 0..1000 km nodes, scale height 268 km above).
//    Between the table's nodes ln rho is interpolated linearly (exponential interpolation), so rho is
//    continuous, positive and strictly decreasing; above 1000 km it continues with the last scale height
//    (the table's own rule), which covers LEO up to 2000 km and beyond. At every node it equals the
//    published density exactly. For speed the model is resampled onto a 1 km grid of (ln rho, slope);
//    the nodes are whole kilometres, so the resampling is exact, and a lookup is one index and one exp.
// 2. ExponentialFitDensity: the 4-term fit shipped with the leo-19647 dataset (best_fit_density.txt):
//      rho(h) = sum_i a_i exp(-(h - c_i) b_i)
//    with a [kg/m^3], b [1/m] and c [m] below, converted from the file's km-based b and c.
#pragma once

#include <array>
#include <vector>

#include "core/physics/deterministic_exp.hpp"

namespace kessler {

class DensityTable {
 public:
  // One node of the published table: altitude [km] and density there [kg/m^3].
  struct Node {
    double altitude_km;
    double density_kg_m3;
  };
  static constexpr double kTopScaleHeight_m = 268.0e3;  // Table 8-4, band above 1000 km

  // The one shared instance (built on first use).
  static const DensityTable& standard();

  double density_kg_m3(double altitude_m) const {
    return density_at(ln_rho_.data(), slope_per_m_.data(), cells_, altitude_m);
  }

  // The lookup on raw arrays, for the propagator's vectorised loop.
  [[gnu::always_inline]] static double density_at(const double* ln_rho, const double* slope_per_m, int cells,
                                                  double altitude_m) {
    double km = altitude_m * 1.0e-3;
    km = km > 0.0 ? km : 0.0;  // also maps NaN to cell 0
    const double top = cells - 1.0;
    km = km < top ? km : top;
    const int cell = static_cast<int>(km);
    return deterministic_exp(ln_rho[cell] + slope_per_m[cell] * (altitude_m - 1000.0 * cell));
  }
  const double* ln_rho() const { return ln_rho_.data(); }
  const double* slope_per_m() const { return slope_per_m_.data(); }
  int cells() const { return cells_; }

  static const std::array<Node, 28>& nodes();

 private:
  DensityTable();
  int cells_ = 0;
  std::vector<double> ln_rho_;       // ln rho at the cell's lower edge (cell k starts at k km)
  std::vector<double> slope_per_m_;  // d ln rho / dh inside the cell [1/m]
};

namespace exponential_fit {
// deploy/datasets/leo-19647/best_fit_density.txt (published with the ESA "cascade" simulator's leo-19647
// test population): lines 1-4 a_i, lines 5-8 b_i [1/km], lines 9-12 c_i [km].
inline constexpr double kA_kg_m3[4] = {1.017099350971841922e-06, 7.864433749696440046e-01,
                                       7.503418833901893756e-09, 8.639342521502260029e-14};
inline constexpr double kB_per_m[4] = {4.638229098022707969e-02 / 1000.0, 1.860800478627226973e-01 / 1000.0,
                                       2.486671755963201086e-02 / 1000.0, 4.810808523935952534e-03 / 1000.0};
inline constexpr double kC_m[4] = {5.015945159890937255e+00 * 1000.0, 2.284298087732807758e+01 * 1000.0,
                                   4.279578287441034412e+00 * 1000.0, 1.562916727761204660e-01 * 1000.0};
}  // namespace exponential_fit

[[gnu::always_inline]] inline double exponential_fit_density_kg_m3(double altitude_m) {
  using namespace exponential_fit;
  return kA_kg_m3[0] * deterministic_exp(-(altitude_m - kC_m[0]) * kB_per_m[0]) +
         kA_kg_m3[1] * deterministic_exp(-(altitude_m - kC_m[1]) * kB_per_m[1]) +
         kA_kg_m3[2] * deterministic_exp(-(altitude_m - kC_m[2]) * kB_per_m[2]) +
         kA_kg_m3[3] * deterministic_exp(-(altitude_m - kC_m[3]) * kB_per_m[3]);
}

}  // namespace kessler
