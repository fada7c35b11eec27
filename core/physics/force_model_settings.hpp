// Which terms of the force model act, as a scenario sets them (all on by default, as in the paper).
#pragma once

namespace kessler {

enum class AtmosphereModel {
  kDensityTable,    // Vallado's exponential atmosphere (Table 8-4), exponential interpolation (default)
  kExponentialFit,  // the 4-term exponential fit shipped with the leo-19647 dataset
};

struct ForceModelSettings {
  bool kepler = true;
  bool j2 = true;
  bool c22_s22 = true;
  bool drag = true;
  bool srp = true;
  bool srp_earth_shadow = true;  // cylindrical shadow; the paper has none
  AtmosphereModel atmosphere = AtmosphereModel::kDensityTable;
};

}  // namespace kessler
