// Sine and cosine written so that a compiler can vectorise loops that call them (no library calls, no
// branches): Cody-Waite reduction by pi/2 and the fdlibm kernel polynomials on [-pi/4, pi/4]
// (about 1 ulp). The same code runs in vector lanes and scalar remainders, so results do not depend on
// which objects share a vector. Valid for |x| < 2^20 pi/2, far beyond SGP4's angles over years.
#pragma once

namespace kessler::sgp4 {

inline void simd_sincos(double x, double& s, double& c) {
  constexpr double kTwoOverPi = 6.36619772367581382433e-01;
  constexpr double kPio2_1 = 1.57079632673412561417e+00;   // first 33 bits of pi/2
  constexpr double kPio2_2 = 6.07710050630396597660e-11;   // next 33 bits
  constexpr double kPio2_2t = 2.02226624879595063154e-21;  // pi/2 - (kPio2_1 + kPio2_2)
  constexpr double kRound = 6755399441055744.0;            // 1.5 * 2^52: adding it rounds to an integer
  const double q = (x * kTwoOverPi + kRound) - kRound;
  const double r = ((x - q * kPio2_1) - q * kPio2_2) - q * kPio2_2t;
  const double z = r * r;
  const double sin_r =
      r + r * z *
              (-1.66666666666666324348e-01 +
               z * (8.33333333332248946124e-03 +
                    z * (-1.98412698298579493134e-04 +
                         z * (2.75573137070700676789e-06 +
                              z * (-2.50507602534068634195e-08 + z * 1.58969099521155010221e-10)))));
  const double cos_r =
      1.0 - 0.5 * z +
      z * z *
          (4.16666666666666019037e-02 +
           z * (-1.38888888888741095749e-03 +
                z * (2.48015872894767294178e-05 +
                     z * (-2.75573143513906633035e-07 +
                          z * (2.08757232129817482790e-09 + z * -1.13596475577881948265e-11)))));
  const long n = static_cast<long>(q) & 3;
  // Quadrant n: sin x = sin r, cos r, -sin r, -cos r; cos x = cos r, -sin r, -cos r, sin r.
  const double s_abs = (n & 1) ? cos_r : sin_r;
  const double c_abs = (n & 1) ? sin_r : cos_r;
  s = (n & 2) ? -s_abs : s_abs;
  c = ((n + 1) & 2) ? -c_abs : c_abs;
}

// x - 2 pi floor(x / 2 pi) style reduction with C fmod's sign convention (result has the sign of x).
inline double simd_fmod_two_pi(double x) {
  constexpr double kTwoPi = 6.28318530717958647692;
  constexpr double kRound = 6755399441055744.0;
  const double ratio = x / kTwoPi;
  double k = (ratio + kRound) - kRound;  // nearest integer
  // Towards zero, as fmod: bitwise & keeps the selects branch-free.
  k = ((k > ratio) & (ratio >= 0.0)) ? k - 1.0 : k;
  k = ((k < ratio) & (ratio < 0.0)) ? k + 1.0 : k;
  return x - k * kTwoPi;
}

}  // namespace kessler::sgp4
