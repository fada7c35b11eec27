#include "core/integration/burn_up.hpp"

#include <cmath>

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
  // Flags in parallel (each depends on its object only), events collected in population order.
#pragma omp parallel for schedule(static) if (n >= 100000)
  for (long i = 0; i < static_cast<long>(n); ++i) {
    const double altitude =
        std::sqrt(x[i] * x[i] + y[i] * y[i] + z[i] * z[i]) - constants::kEarthEquatorialRadius_m;
    flag[i] = !(altitude >= min_altitude_m);  // a NaN state also leaves
  }
  std::vector<BurnUp> events;
  for (std::size_t i = 0; i < n; ++i)
    if (flag[i])
      events.push_back(
          {population.id[i], time_s,
           std::sqrt(x[i] * x[i] + y[i] * y[i] + z[i] * z[i]) - constants::kEarthEquatorialRadius_m});
  return events;
}

}  // namespace kessler
