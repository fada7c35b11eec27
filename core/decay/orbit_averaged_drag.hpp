// How fast drag shrinks an orbit's semi-major axis in a given atmosphere, per unit of ballistic
// coefficient: the orbit average of
//   da/dt = (2 a^2 / mu) v . a_drag,   a_drag = -1/2 rho (Cd A/m) |v_rel| v_rel,   v_rel = v - omega_E x r
// (the energy equation, E = -mu / 2a; the force model's drag, core/physics/drag.hpp) with Cd A/m = 1.
// The orbit is the element set's, by SGP4, over one revolution from its epoch: each sample at its own
// time, so the atmosphere's local-time, latitude and day-to-day variations are in the average.
// Samples are uniform in eccentric anomaly E and weighted by dt/dE = (1 - e cos E) / n, which puts more
// of them near perigee than uniform time steps would.
#pragma once

#include <functional>
#include <optional>

#include <Eigen/Core>

#include "core/sgp4/sgp4.hpp"
#include "core/time/epoch.hpp"

namespace kessler {

// The run's atmosphere: density [kg/m^3] at a TEME position [m] at an instant (UTC).
using DensityAt = std::function<double(const UtcEpoch& when, const Eigen::Vector3d& r_teme_m)>;

// <da/dt> [m/s per m^2/kg] (negative) over the revolution that starts at the element set's epoch;
// nullopt when SGP4 cannot propagate it (decayed, bad elements).
std::optional<double> orbit_averaged_decay_per_unit_ballistic(const Sgp4Record& record, const UtcEpoch& epoch,
                                                              const DensityAt& density);

}  // namespace kessler
