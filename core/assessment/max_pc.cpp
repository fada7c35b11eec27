#include "core/assessment/max_pc.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace kessler::assessment {

MaxPc max_pc(const EncounterGeometry& g, double hard_body_radius_m) {
  const double v = (g.miss_x_m * g.miss_x_m) / (g.sigma_x_m * g.sigma_x_m) +
                   (g.miss_y_m * g.miss_y_m) / (g.sigma_y_m * g.sigma_y_m);
  if (!(v > 0.0)) return {1.0, 0.0};
  const double pc =
      hard_body_radius_m * hard_body_radius_m / (std::numbers::e * g.sigma_x_m * g.sigma_y_m * v);
  return {std::min(pc, 1.0), std::sqrt(0.5 * v)};
}

}  // namespace kessler::assessment
