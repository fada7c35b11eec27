// Fragment sizes: the cumulative power law N(>= Lc) ~ Lc^-k truncated to [Lc_min, Lc_max], drawn by its
// inverse CDF, and the cross-section area A(Lc) of the model.
#pragma once

#include <cmath>
#include <cstdint>

namespace kessler {

class TruncatedPowerLaw {
 public:
  // Sizes in [lc_min, lc_max] (lc_min < lc_max) with P(size >= L) proportional to L^-k - lc_max^-k.
  TruncatedPowerLaw(double lc_min_m, double lc_max_m, double exponent)
      : k_(exponent), low_(std::pow(lc_min_m, -exponent)), high_(std::pow(lc_max_m, -exponent)) {}

  // ln(L) for the size with P(size >= L) = u, u in (0, 1]: L^-k = Lmax^-k + u (Lmin^-k - Lmax^-k).
  double log_size(double u) const { return -std::log(high_ + u * (low_ - high_)) / k_; }

  // P(size >= L) for L in [lc_min, lc_max].
  double fraction_at_least(double lc_m) const { return (std::pow(lc_m, -k_) - high_) / (low_ - high_); }

 private:
  double k_, low_, high_;
};

// Stratified draws: fragment i of n takes stratum s(i) = (a i + b) mod n (a bijection of 0..n-1, with a
// coprime to n) and u = (s(i) + jitter) / n, jitter uniform in (0, 1). The n sizes then follow the power
// law to within one fragment at every size, yet fragment i's size depends only on (seed, event, i, n)
// and the index order carries no size order.
class SizeStrata {
 public:
  SizeStrata(std::uint64_t n, std::uint64_t offset_bits);
  // Fragment i's stratum; stratum 0 holds the largest sizes.
  std::uint64_t stratum(std::uint64_t i) const {
    return static_cast<std::uint64_t>((static_cast<unsigned __int128>(a_) * i + b_) % n_);
  }
  // P(size >= L) of a fragment in stratum s.
  double uniform(std::uint64_t s, double jitter) const {
    return (static_cast<double>(s) + jitter) / static_cast<double>(n_);
  }

 private:
  std::uint64_t n_ = 1, a_ = 1, b_ = 0;
};

// A(Lc) [m^2]: 0.540424 Lc^2 below 1.67 mm, else 0.556945 Lc^2.0047077 (Lc in m). From ln(Lc).
inline double area_from_log_size(double log_lc) {
  constexpr double kSmallLimitLog = -6.394931652553473;  // ln(0.00167)
  if (log_lc < kSmallLimitLog) return 0.540424 * std::exp(2.0 * log_lc);
  return 0.556945 * std::exp(2.0047077 * log_lc);
}

inline double area_from_size(double lc_m) {
  return area_from_log_size(std::log(lc_m));
}

}  // namespace kessler
