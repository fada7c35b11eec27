// exp(x) from + - * and bit operations only, so a vectorised loop and its scalar remainder give the same
// bits (libm's exp is a call the vectoriser cannot inline, and its vector variants need fast-math).
//
// Method: Cody-Waite reduction x = k ln2 + r, |r| <= ln2/2, then a degree-13 Taylor polynomial for e^r
// (truncation below 1e-17 relative) and 2^k built in the exponent field. Accuracy about 2 ulp on
// [-700, 700]; arguments outside are clamped there (densities never need more).
#pragma once

#include <bit>
#include <cstdint>

namespace kessler {

[[gnu::always_inline]] inline double deterministic_exp(double x) {
  x = x < -700.0 ? -700.0 : x;
  x = x > 700.0 ? 700.0 : x;
  constexpr double kLog2e = 1.4426950408889634;
  constexpr double kRoundShifter = 6755399441055744.0;   // 1.5 * 2^52: adding it rounds to an integer
  constexpr double kLn2Hi = 6.93147180369123816490e-01;  // ln2 split so that k * kLn2Hi is exact
  constexpr double kLn2Lo = 1.90821492927058770002e-10;
  const double shifted = x * kLog2e + kRoundShifter;
  const double k = shifted - kRoundShifter;
  double r = x - k * kLn2Hi;
  r = r - k * kLn2Lo;
  // Horner form of sum r^n / n!, n = 0..13.
  double p = 1.0 / 6227020800.0;
  p = p * r + 1.0 / 479001600.0;
  p = p * r + 1.0 / 39916800.0;
  p = p * r + 1.0 / 3628800.0;
  p = p * r + 1.0 / 362880.0;
  p = p * r + 1.0 / 40320.0;
  p = p * r + 1.0 / 5040.0;
  p = p * r + 1.0 / 720.0;
  p = p * r + 1.0 / 120.0;
  p = p * r + 1.0 / 24.0;
  p = p * r + 1.0 / 6.0;
  p = p * r + 0.5;
  p = p * r + 1.0;
  p = p * r + 1.0;
  // The low mantissa bits of `shifted` hold k (two's complement, mod 2^51); shifted into the exponent
  // field with the bias they give 2^k exactly.
  const std::uint64_t scale_bits = (std::bit_cast<std::uint64_t>(shifted) + 1023u) << 52;
  return p * std::bit_cast<double>(scale_bits);
}

}  // namespace kessler
