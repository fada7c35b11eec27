// The density a run's force model sees, as a plain function of time and TEME position, for fits and
// checks outside the propagator's loop: the density table or the leo-19647 fit by altitude, or the full
// NRLMSISE-00 model with the run's solar activity (the propagator reads a grid of it, within 1 %).
#pragma once

#include <string>

#include "core/decay/orbit_averaged_drag.hpp"
#include "core/physics/force_model_settings.hpp"
#include "core/time/epoch.hpp"

namespace kessler {

// `start_epoch` is the run's (NRLMSISE-00 places its grid's frame there). Thread-safe.
DensityAt run_atmosphere_density(const ForceModelSettings& settings, const UtcEpoch& start_epoch);

// "density table", "exponential fit", "NRLMSISE-00 (observed solar activity)", ...
std::string run_atmosphere_name(const ForceModelSettings& settings);

}  // namespace kessler
