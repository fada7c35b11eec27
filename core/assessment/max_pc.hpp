// The maximum collision probability over the size of the covariance, for a covariance of known shape
// but unknown scale (Alfriend et al. 1999; Alfano 2005): with the combined covariance k^2 C and a
// hard-body radius R small against it,
//   Pc(k) ~= R^2 / (2 k^2 sx sy) exp(-v / (2 k^2)),   v = x^2 / sx^2 + y^2 / sy^2,
// largest at k^2 = v / 2 with
//   Pc_max = R^2 / (e sx sy v).
// (x, y, sx, sy: the encounter-plane miss and sigmas of C.) SOCRATES reports this with each object's
// covariance shaped 100 / 300 / 100 m (radial, in-track, cross-track); the "dilution" sigma is the
// scale at the maximum: a smaller covariance makes the conjunction less likely, not more.
#pragma once

#include "core/assessment/encounter_plane.hpp"

namespace kessler::assessment {

struct MaxPc {
  double pc_max = 0.0;
  double scale = 0.0;  // k at the maximum (0 when the miss is zero: Pc -> 1 as k -> 0)
};

// geometry: the encounter plane of the unscaled shape C.
MaxPc max_pc(const EncounterGeometry& geometry, double hard_body_radius_m);

}  // namespace kessler::assessment
