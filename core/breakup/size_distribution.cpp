#include "core/breakup/size_distribution.hpp"

#include <numeric>

namespace kessler {

SizeStrata::SizeStrata(std::uint64_t n, std::uint64_t offset_bits) : n_(n == 0 ? 1 : n) {
  // A multiplier near n / golden ratio spreads neighbouring indices across the size range.
  a_ = static_cast<std::uint64_t>(static_cast<double>(n_) * 0.6180339887498949) | 1u;
  while (std::gcd(a_, n_) != 1) ++a_;
  a_ %= n_;
  if (a_ == 0) a_ = 1;  // n = 1 (or 2): any multiplier coprime to n
  b_ = offset_bits % n_;
}

}  // namespace kessler
