// Which terms of the force model act, as a scenario sets them (all on by default, as in the paper).
#pragma once

#include <memory>

#include "core/physics/space_weather.hpp"

namespace kessler {

enum class AtmosphereModel {
  kDensityTable,    // Vallado's exponential atmosphere (Table 8-4), exponential interpolation (default)
  kExponentialFit,  // the 4-term exponential fit shipped with the leo-19647 dataset
  kNrlmsise00,      // NRLMSISE-00 driven by solar activity, read from a grid (msis_grid.hpp)
};

struct ForceModelSettings {
  bool kepler = true;
  bool j2 = true;
  bool c22_s22 = true;
  bool drag = true;
  bool srp = true;
  bool srp_earth_shadow = true;  // cylindrical shadow; the paper has none
  AtmosphereModel atmosphere = AtmosphereModel::kDensityTable;
  // kNrlmsise00 only: where its solar activity comes from, and the table for the observed and cycle
  // modes (SpaceWeather::bundled() when null).
  SolarActivitySettings solar_activity;
  std::shared_ptr<const SpaceWeather> space_weather;
};

}  // namespace kessler
