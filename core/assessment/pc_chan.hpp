// Chan's series for the 2-D collision probability (Chan 1997; Chan, "Spacecraft Collision Probability",
// 2008): the hard-body disk replaced by an ellipse of equal area in the covariance's principal axes,
// which turns the integral into a convergent series in u = R^2 / (sigma_x sigma_y) and
// v = x^2 / sigma_x^2 + y^2 / sigma_y^2:
//   Pc = sum_m Poisson(m; v/2) * P(Poisson(u/2) > m).
// Fast (a handful of terms for a small disk far from the mean); agrees with Foster's integral where the
// disk is small against the covariance (see README).
#pragma once

#include "core/assessment/encounter_plane.hpp"

namespace kessler::assessment {

double pc_chan(const EncounterGeometry& geometry, double hard_body_radius_m);

// Estimated relative error of Chan's series from replacing the disk by the equal-area ellipse, to
// leading order: (1 + v) (R / sigma_min)^2 / 8 (the density's curvature across the disk at the
// Mahalanobis miss sqrt(v), and the ellipse's spread at the mean).
double chan_relative_error_estimate(const EncounterGeometry& geometry, double hard_body_radius_m);

}  // namespace kessler::assessment
