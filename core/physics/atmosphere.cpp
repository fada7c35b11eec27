#include "core/physics/atmosphere.hpp"

#include <cmath>

namespace kessler {

const std::array<DensityTable::Node, 28>& DensityTable::nodes() {
  // Vallado (2013), Table 8-4: base altitude [km] and nominal density [kg/m^3].
  static const std::array<Node, 28> kNodes = {{
      {0, 1.225},       {25, 3.899e-2},   {30, 1.774e-2},    {40, 3.972e-3},   {50, 1.057e-3},
      {60, 3.206e-4},   {70, 8.770e-5},   {80, 1.905e-5},    {90, 3.396e-6},   {100, 5.297e-7},
      {110, 9.661e-8},  {120, 2.438e-8},  {130, 8.484e-9},   {140, 3.845e-9},  {150, 2.070e-9},
      {180, 5.464e-10}, {200, 2.789e-10}, {250, 7.248e-11},  {300, 2.418e-11}, {350, 9.518e-12},
      {400, 3.725e-12}, {450, 1.585e-12}, {500, 6.967e-13},  {600, 1.454e-13}, {700, 3.614e-14},
      {800, 1.170e-14}, {900, 5.245e-15}, {1000, 3.019e-15},
  }};
  return kNodes;
}

const DensityTable& DensityTable::standard() {
  static const DensityTable table;
  return table;
}

DensityTable::DensityTable() {
  // 1 km cells up to 2500 km; the last cell's slope (the 268 km scale height) extends upward.
  cells_ = 2501;
  ln_rho_.resize(cells_);
  slope_per_m_.resize(cells_);
  const auto& n = nodes();
  std::size_t band = 0;
  for (int k = 0; k < cells_; ++k) {
    while (band + 1 < n.size() && n[band + 1].altitude_km <= k) ++band;
    const double ln0 = std::log(n[band].density_kg_m3);
    double slope;
    if (band + 1 < n.size())
      slope = (std::log(n[band + 1].density_kg_m3) - ln0) /
              ((n[band + 1].altitude_km - n[band].altitude_km) * 1000.0);
    else
      slope = -1.0 / kTopScaleHeight_m;
    slope_per_m_[k] = slope;
    ln_rho_[k] = ln0 + slope * ((k - n[band].altitude_km) * 1000.0);
  }
}

}  // namespace kessler
