#include "core/conjunctions/object_step.hpp"

namespace kessler {

void hermite_state(const ObjectStep& o, double dt_s, double tau_s, double r_m[3], double v_m_s[3]) {
  const double s = tau_s / dt_s;
  const double s2 = s * s, s3 = s2 * s;
  // Cubic Hermite basis on s in [0, 1] and its derivatives (d/ds).
  const double h00 = 2.0 * s3 - 3.0 * s2 + 1.0, h10 = s3 - 2.0 * s2 + s;
  const double h01 = -2.0 * s3 + 3.0 * s2, h11 = s3 - s2;
  const double d00 = 6.0 * s2 - 6.0 * s, d10 = 3.0 * s2 - 4.0 * s + 1.0;
  const double d01 = -6.0 * s2 + 6.0 * s, d11 = 3.0 * s2 - 2.0 * s;
  for (int k = 0; k < 3; ++k) {
    const double m0 = dt_s * o.v0[k], m1 = dt_s * o.v1[k];
    r_m[k] = h00 * o.p0[k] + h10 * m0 + h01 * o.p1[k] + h11 * m1;
    v_m_s[k] = (d00 * o.p0[k] + d10 * m0 + d01 * o.p1[k] + d11 * m1) / dt_s;
  }
}

void linear_state(const ObjectStep& o, double tau_s, double r_m[3], double v_m_s[3]) {
  for (int k = 0; k < 3; ++k) {
    r_m[k] = o.p0[k] + tau_s * o.v0[k];
    v_m_s[k] = o.v0[k];
  }
}

}  // namespace kessler
