#include "core/integration/burn_up.hpp"

#include <cmath>

#include <omp.h>

#include "core/integration/thread_chunks.hpp"
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
  // Each thread flags the chunk it propagated (thread_chunks.hpp), so no core reads positions another
  // core has just written.
  const int threads = n >= kPropagationParallelMinimum ? omp_get_max_threads() : 1;
#pragma omp parallel num_threads(threads)
  {
    const auto [begin, end] = thread_chunk(n, static_cast<std::size_t>(omp_get_thread_num()),
                                           static_cast<std::size_t>(omp_get_num_threads()));
#pragma omp simd
    for (std::size_t i = begin; i < end; ++i)
      flag[i] = !(x[i] * x[i] + y[i] * y[i] + z[i] * z[i] >= min_radius2);  // a NaN state also leaves
  }
  std::vector<BurnUp> events;
  for_each_flagged(flag, 0, n, [&](std::size_t i) {
    events.push_back(
        {population.id[i], time_s,
         std::sqrt(x[i] * x[i] + y[i] * y[i] + z[i] * z[i]) - constants::kEarthEquatorialRadius_m});
  });
  return events;
}

}  // namespace kessler
