#include "core/integration/burn_up.hpp"

#include <cmath>
#include <cstring>

#include <omp.h>

#include "core/physics/constants.hpp"

namespace kessler {

std::vector<BurnUp> find_burn_ups(const Population& population, double min_altitude_m, double time_s,
                                  std::vector<char>& flags) {
  const std::size_t n = population.size();
  flags.assign(n, 0);
  const StateArrays& s = population.state;
  const double* x = s.x.data();
  const double* y = s.y.data();
  const double* z = s.z.data();
  char* flag = flags.data();
  // Flags in parallel (each depends on its object only), events collected in population order. The
  // test compares squared radii (no square root per object); r^2 >= (R + h)^2 is r >= R + h for r >= 0.
  const double min_radius_m = constants::kEarthEquatorialRadius_m + min_altitude_m;
  const double min_radius2 = min_radius_m > 0.0 ? min_radius_m * min_radius_m : 0.0;
  // Each thread flags the chunk it propagated (the same static split), so no core reads positions
  // another core has just written. A team of one for tiny populations (not an `if` clause, which GCC
  // runs unvectorised).
  const int threads = n >= 512 ? omp_get_max_threads() : 1;
#pragma omp parallel for simd schedule(static) num_threads(threads)
  for (long i = 0; i < static_cast<long>(n); ++i)
    flag[i] = !(x[i] * x[i] + y[i] * y[i] + z[i] * z[i] >= min_radius2);  // a NaN state also leaves
  std::vector<BurnUp> events;
  if (n == 0) return events;
  // Burn-ups are rare: jump from flag to flag.
  for (const char* p = flag; (p = static_cast<const char*>(std::memchr(p, 1, n - (p - flag)))) != nullptr;
       ++p) {
    const std::size_t i = static_cast<std::size_t>(p - flag);
    events.push_back(
        {population.id[i], time_s,
         std::sqrt(x[i] * x[i] + y[i] * y[i] + z[i] * z[i]) - constants::kEarthEquatorialRadius_m});
    if (i + 1 == n) break;
  }
  return events;
}

}  // namespace kessler
