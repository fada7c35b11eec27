#include "core/integration/burn_up.hpp"

#include <cmath>

#include <omp.h>

#include "core/parallel/thread_chunks.hpp"
#include "core/physics/constants.hpp"

namespace kessler {

double burn_up_radius2(double min_altitude_m) {
  const double radius_m = constants::kEarthEquatorialRadius_m + min_altitude_m;
  return radius_m > 0.0 ? radius_m * radius_m : 0.0;
}

void flag_burn_ups(const StateArrays& s, double radius2, std::vector<char>& flags) {
  const std::size_t n = s.size();
  flags.resize(n);
  const double* x = s.x.data();
  const double* y = s.y.data();
  const double* z = s.z.data();
  char* flag = flags.data();
  // Each thread flags the chunk it propagated (thread_chunks.hpp), so no core reads positions another
  // core has just written.
  const int threads = n >= kPropagationParallelMinimum ? omp_get_max_threads() : 1;
#pragma omp parallel num_threads(threads)
  {
    const ThreadChunk chunk = thread_chunk(n, static_cast<std::size_t>(omp_get_thread_num()),
                                           static_cast<std::size_t>(omp_get_num_threads()));
#pragma omp simd
    for (std::size_t i = chunk.begin; i < chunk.end; ++i) flag[i] = burns_up(x[i], y[i], z[i], radius2);
  }
}

std::vector<BurnUp> flagged_burn_ups(const Population& population, double time_s,
                                     const std::vector<char>& flags) {
  const StateArrays& s = population.state;
  std::vector<BurnUp> events;
  for_each_flagged(flags.data(), 0, population.size(), [&](std::size_t i) {
    const double r = std::sqrt(s.x[i] * s.x[i] + s.y[i] * s.y[i] + s.z[i] * s.z[i]);
    events.push_back({population.id[i], time_s, r - constants::kEarthEquatorialRadius_m});
  });
  return events;
}

std::vector<BurnUp> find_burn_ups(const Population& population, double min_altitude_m, double time_s,
                                  std::vector<char>& flags) {
  flag_burn_ups(population.state, burn_up_radius2(min_altitude_m), flags);
  return flagged_burn_ups(population, time_s, flags);
}

}  // namespace kessler
