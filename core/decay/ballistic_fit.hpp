// Ballistic coefficients fitted in the run's own atmosphere. A catalog object's Cd A/m is the value that
// makes the run's drag (its atmosphere at the element set's epoch and solar activity, co-rotating)
// reproduce the decay rate the element set observed:
//   Cd A/m = (da/dt observed) / <da/dt per unit Cd A/m in the run's atmosphere>
// (observed_decay.hpp, orbit_averaged_drag.hpp). Why: BSTAR is fitted against SGP4's own power-law
// atmosphere, which above ~500 km is far denser than the real thermosphere at solar minimum; carried into
// another atmosphere by Cd A/m = 2 B* / rho0 it makes high objects decay several times too slowly.
// A ballistic coefficient only means something in the density model it was estimated with.
//
// Signals, in order: the element set's mean-motion derivative, then SGP4's decay from its BSTAR (when
// n-dot is not positive), then none: the object keeps the ingest's rule (2 B* / rho0, or Cd 2.2 with its
// size; core/catalog/object_properties.hpp). Results outside [min, max] are clamped and counted.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "core/decay/observed_decay.hpp"
#include "core/decay/orbit_averaged_drag.hpp"
#include "core/population/population.hpp"
#include "core/sgp4/mean_elements.hpp"

namespace kessler {

struct BallisticFitSettings {
  // The first signal tried; the other is the fallback.
  DecaySignal first_signal = DecaySignal::kMeanMotionDerivative;
  // Bounds on the fitted Cd A/m [m^2/kg]: 1e-4 is a dense, compact rocket body; 10 is thin insulation
  // foil (Cd 2.2, A/m 4.5), the lightest catalogued debris.
  double min_m2_kg = 1.0e-4;
  double max_m2_kg = 10.0;
  // Element sets older than this at the start are counted as stale (still fitted at their own epoch).
  double stale_after_days = 30.0;
};

// What the fit did, for the ingest report.
struct BallisticFitCounts {
  std::string atmosphere;  // the atmosphere fitted in, for the report
  std::size_t from_mean_motion_derivative = 0;
  std::size_t from_sgp4_bstar = 0;
  std::size_t no_signal = 0;  // kept the ingest's rule
  std::size_t clamped_low = 0, clamped_high = 0;
  std::size_t stale = 0;
  // Median over the fitted objects of fitted Cd A/m / (2 B* / rho0) (objects with B* > 0).
  double median_ratio_to_bstar_mapping = 0.0;
};

// Fits drag_area_to_mass_m2_kg of population[i] from elements[i] (index-aligned) in `density`, on the
// calling thread's OpenMP team (each object is independent, so any thread count gives the same bits).
BallisticFitCounts fit_ballistic_coefficients(Population& population,
                                              const std::vector<MeanElements>& elements,
                                              const UtcEpoch& start_epoch, const DensityAt& density,
                                              const BallisticFitSettings& settings = {});

}  // namespace kessler
