// Foster's collision probability (Foster and Estes 1992): the 2-D Gaussian of the combined covariance
// in the encounter plane integrated numerically over the hard-body disk. The reference method.
#pragma once

#include "core/assessment/encounter_plane.hpp"

namespace kessler::assessment {

// Pc of a disk of radius hard_body_radius_m centred on the origin under N(miss, diag(sigma^2)).
// The integral over the axis of the smaller sigma is done in closed form (erf); the one over the other
// axis adaptively (Gauss-Kronrod 7/15, relative tolerance 1e-12) after the substitution t = R sin(theta)
// that removes the disk edge's square-root singularity.
double pc_foster(const EncounterGeometry& geometry, double hard_body_radius_m);

}  // namespace kessler::assessment
