// The area-to-mass ratio: chi = log10(A/m [m^2/kg]) given the fragment size, from the model's
// size-dependent distributions (lambda = log10(Lc [m])):
//   Lc < 8 cm:   one normal, the small-fragment distribution (either object class);
//   Lc > 11 cm:  a mixture alpha N(mu1, sigma1) + (1 - alpha) N(mu2, sigma2), spacecraft or rocket body;
//   8 - 11 cm:   the bridge, a mixture of the two with the large-fragment weight (Lc - 8 cm) / 3 cm.
#pragma once

#include "core/breakup/breakup_event.hpp"

namespace kessler {

struct AreaToMassBimodal {
  double alpha, mu1, sigma1, mu2, sigma2;
};

inline double small_fragment_mean(double lambda) {
  if (lambda <= -1.75) return -0.3;
  if (lambda < -1.25) return -0.3 - 1.4 * (lambda + 1.75);
  return -1.0;
}

inline double small_fragment_sigma(double lambda) {
  if (lambda <= -3.5) return 0.2;
  return 0.2 + 0.1333 * (lambda + 3.5);
}

inline AreaToMassBimodal spacecraft_area_to_mass(double l) {
  AreaToMassBimodal p;
  p.alpha = l <= -1.95 ? 0.0 : (l < 0.55 ? 0.3 + 0.4 * (l + 1.2) : 1.0);
  p.mu1 = l <= -1.1 ? -0.6 : (l < 0.0 ? -0.6 - 0.318 * (l + 1.1) : -0.95);
  p.sigma1 = l <= -1.3 ? 0.1 : (l < -0.3 ? 0.1 + 0.2 * (l + 1.3) : 0.3);
  p.mu2 = l <= -0.7 ? -1.2 : (l < -0.1 ? -1.2 - 1.333 * (l + 0.7) : -2.0);
  p.sigma2 = l <= -0.5 ? 0.5 : (l < -0.3 ? 0.5 - (l + 0.5) : 0.3);
  return p;
}

inline AreaToMassBimodal rocket_body_area_to_mass(double l) {
  AreaToMassBimodal p;
  p.alpha = l <= -1.4 ? 1.0 : (l < 0.0 ? 1.0 - 0.3571 * (l + 1.4) : 0.5);
  p.mu1 = l <= -0.5 ? -0.45 : (l < 0.0 ? -0.45 - 0.9 * (l + 0.5) : -0.9);
  p.sigma1 = 0.55;
  p.mu2 = -0.9;
  // The paper's +0.28 - 0.1636 (lambda + 1); one public implementation has -0.28 here (a sign error).
  p.sigma2 = l <= -1.0 ? 0.28 : (l < 0.1 ? 0.28 - 0.1636 * (l + 1.0) : 0.1);
  return p;
}

// Weight of the large-fragment distribution: 0 below 8 cm, 1 above 11 cm, linear in Lc between.
inline double large_fragment_weight(double lc_m) {
  if (lc_m <= 0.08) return 0.0;
  if (lc_m >= 0.11) return 1.0;
  return (lc_m - 0.08) / 0.03;
}

// chi = log10(A/m) for a fragment of size lc_m (lambda = log10 lc_m) from two uniforms in (0, 1) and a
// standard normal z.
// The model's densities are mixtures (the bimodal laws and the 8-11 cm bridge); we sample them as the
// paper defines a mixture: pick the component with its weight (u_branch: small or large law, u_component:
// first or second normal), then draw that normal. Not a weighted blend of two draws.
inline double sample_log_area_to_mass(double lc_m, double lambda, BreakupObjectClass object_class,
                                      double u_branch, double u_component, double z) {
  if (u_branch >= large_fragment_weight(lc_m))
    return small_fragment_mean(lambda) + small_fragment_sigma(lambda) * z;
  const AreaToMassBimodal p = object_class == BreakupObjectClass::kRocketBody
                                  ? rocket_body_area_to_mass(lambda)
                                  : spacecraft_area_to_mass(lambda);
  return u_component < p.alpha ? p.mu1 + p.sigma1 * z : p.mu2 + p.sigma2 * z;
}

}  // namespace kessler
