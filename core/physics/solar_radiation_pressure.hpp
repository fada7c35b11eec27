// Solar radiation pressure on a sphere (reflectivity folded into A/m), as in the paper:
//   a = P AU^2 (A/m) (r - r_sun) / |r - r_sun|^3,   P = 4.56e-6 N/m^2 at 1 AU,
// i.e. magnitude P (A/m) (AU/|r - r_sun|)^2, directed away from the Sun. The paper has no shadow; here
// a cylindrical Earth shadow (Vallado sec. 5.3.1, the cylindrical model) switches it off: the object is
// in shadow when it is behind the Earth (r . s_hat < 0) and within one Earth radius of the Sun-Earth
// line (|r|^2 - (r . s_hat)^2 < R_E^2).
#pragma once

#include <cmath>

namespace kessler {

struct SunGeometry {
  double x_m = 0, y_m = 0, z_m = 0;  // Sun position, TEME [m]
  double ux = 0, uy = 0, uz = 0;     // unit vector towards the Sun
  double shadow_radius2_m2 = 0;      // R_E^2, or negative to disable the shadow
};

// p_au2 = P AU^2 [N] (zero switches the term off); srp_area_to_mass = A/m [m^2/kg].
[[gnu::always_inline]] inline void srp_acceleration(double p_au2, const SunGeometry& sun,
                                                    double srp_area_to_mass_m2_kg, double x, double y,
                                                    double z, double& ax, double& ay, double& az) {
  const double dx = x - sun.x_m;
  const double dy = y - sun.y_m;
  const double dz = z - sun.z_m;
  const double inv_d = 1.0 / std::sqrt(dx * dx + dy * dy + dz * dz);
  const double along = x * sun.ux + y * sun.uy + z * sun.uz;
  const double off_axis2 = x * x + y * y + z * z - along * along;
  const bool lit = (along >= 0.0) | (off_axis2 >= sun.shadow_radius2_m2);  // no short-circuit: no branch
  const double f = lit ? p_au2 * srp_area_to_mass_m2_kg * inv_d * inv_d * inv_d : 0.0;
  ax = f * dx;
  ay = f * dy;
  az = f * dz;
}

}  // namespace kessler
