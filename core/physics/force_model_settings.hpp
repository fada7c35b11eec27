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

// How the symplectic propagator couples drag, which depends on velocity, to its composition
// (symplectic_propagator.hpp):
//  - kEveryKick: each kick is drag's exact flow over h/2, the conservative kick, the flow again: the
//    step stays 4th order with drag; the density is read at every kick (7 per step with blanes_moan4).
//  - kStepEnds: drag's exact flow over dt/2 at the step's start, the conservative composition, the flow
//    over dt/2 at its end (a Strang splitting of drag around the step): 2nd order in drag, 2 density
//    reads per step, about half the cost of a step with drag. Its error is a fraction of drag's own
//    effect, ~(dt/T)^2 (tests/physics/integrator_test.cpp), far below the atmosphere's uncertainty.
enum class DragCoupling { kEveryKick, kStepEnds };

struct ForceModelSettings {
  bool kepler = true;
  bool j2 = true;
  bool c22_s22 = true;
  bool drag = true;
  bool srp = true;
  bool srp_earth_shadow = true;  // cylindrical shadow; the paper has none
  AtmosphereModel atmosphere = AtmosphereModel::kDensityTable;
  DragCoupling drag_coupling = DragCoupling::kEveryKick;
  // kNrlmsise00 only: where its solar activity comes from, and the table for the observed and cycle
  // modes (SpaceWeather::bundled() when null).
  SolarActivitySettings solar_activity;
  std::shared_ptr<const SpaceWeather> space_weather;
};

}  // namespace kessler
