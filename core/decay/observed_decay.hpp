// An object's observed decay rate, read from its element set: how fast its mean semi-major axis shrinks
// at the element set's epoch [m/s, negative while decaying]. Two signals an element set carries:
//  - the mean-motion derivative (TLE line 1, columns 34-43: n-dot / 2): n-dot is the rate the orbit
//    determination saw, and for a drag-dominated orbit da/dt = -(2/3) (a / n) n-dot (Kepler's third law);
//  - BSTAR through SGP4: SGP4's mean semi-major axis decays as a(t) = a0 (1 - C1 t - ...)^2, C1 = B* C2
//    (Hoots & Roehrich, Spacetrack Report #3), so at epoch da/dt = -2 a0 C1. BSTAR was fitted so that
//    SGP4's fixed power-law atmosphere reproduces the observed decay over the fit span; C1 carries that
//    rate, not the atmosphere's density.
// Either rate, divided by the decay the run's own atmosphere gives one unit of Cd A/m
// (orbit_averaged_drag.hpp), is the object's ballistic coefficient in that atmosphere (ballistic_fit.hpp).
#pragma once

#include <optional>

#include "core/sgp4/mean_elements.hpp"
#include "core/sgp4/sgp4.hpp"

namespace kessler {

enum class DecaySignal {
  kMeanMotionDerivative,  // the element set's n-dot
  kSgp4Bstar,             // SGP4's decay with the element set's BSTAR
};

// The mean semi-major axis [m] of an initialised element set (SGP4's un-Kozai'd mean motion, WGS-72).
double sgp4_mean_semi_major_axis_m(const Sgp4Record& record);

// da/dt [m/s] at the element set's epoch by `signal`; nullopt when the signal says the orbit is not
// decaying (n-dot <= 0, B* <= 0) or the record could not be initialised.
std::optional<double> observed_decay_rate_m_s(const MeanElements& elements, const Sgp4Record& record,
                                              DecaySignal signal);

}  // namespace kessler
