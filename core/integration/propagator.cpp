#include "core/integration/propagator.hpp"

#include "core/integration/burn_up.hpp"

namespace kessler {

void Propagator::step_with(Population& population, double t_start_s, double dt_s,
                           const StepRequest& request) {
  if (request.start_out != nullptr) *request.start_out = population.state;
  step(population, t_start_s, dt_s);
  if (request.end_out != nullptr) *request.end_out = population.state;
  if (request.burn_up_flags != nullptr)
    flag_burn_ups(population.state, request.burn_up_radius2, *request.burn_up_flags);
}

}  // namespace kessler
