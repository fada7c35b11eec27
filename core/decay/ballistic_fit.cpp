#include "core/decay/ballistic_fit.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "core/physics/constants.hpp"

namespace kessler {
namespace {

enum class FitSource : std::uint8_t { kNone, kMeanMotionDerivative, kSgp4Bstar };

struct ObjectFit {
  FitSource source = FitSource::kNone;
  double value_m2_kg = 0.0;
  int clamped = 0;  // -1 low, +1 high
};

ObjectFit fit_one(const MeanElements& elements, const DensityAt& density,
                  const BallisticFitSettings& settings) {
  ObjectFit out;
  const Sgp4Record record = sgp4_initialise(elements);
  const DecaySignal second = settings.first_signal == DecaySignal::kMeanMotionDerivative
                                 ? DecaySignal::kSgp4Bstar
                                 : DecaySignal::kMeanMotionDerivative;
  std::optional<double> rate;
  DecaySignal used = settings.first_signal;
  for (DecaySignal signal : {settings.first_signal, second}) {
    rate = observed_decay_rate_m_s(elements, record, signal);
    used = signal;
    if (rate) break;
  }
  if (!rate) return out;
  const std::optional<double> per_unit =
      orbit_averaged_decay_per_unit_ballistic(record, elements.epoch, density);
  if (!per_unit || !(*per_unit < 0.0)) return out;
  double value = *rate / *per_unit;
  if (!std::isfinite(value)) return out;
  if (value < settings.min_m2_kg) {
    value = settings.min_m2_kg;
    out.clamped = -1;
  } else if (value > settings.max_m2_kg) {
    value = settings.max_m2_kg;
    out.clamped = 1;
  }
  out.source =
      used == DecaySignal::kMeanMotionDerivative ? FitSource::kMeanMotionDerivative : FitSource::kSgp4Bstar;
  out.value_m2_kg = value;
  return out;
}

}  // namespace

BallisticFitCounts fit_ballistic_coefficients(Population& population,
                                              const std::vector<MeanElements>& elements,
                                              const UtcEpoch& start_epoch, const DensityAt& density,
                                              const BallisticFitSettings& settings) {
  if (elements.size() != population.size())
    throw std::invalid_argument("fit_ballistic_coefficients: elements and population differ in size");
  const auto n = static_cast<std::int64_t>(population.size());
  std::vector<ObjectFit> fits(population.size());
#pragma omp parallel for schedule(dynamic, 32)
  for (std::int64_t i = 0; i < n; ++i) fits[i] = fit_one(elements[i], density, settings);

  BallisticFitCounts counts;
  std::vector<double> ratios;
  for (std::size_t i = 0; i < fits.size(); ++i) {
    const ObjectFit& f = fits[i];
    if (start_epoch.seconds_since(elements[i].epoch) > settings.stale_after_days * constants::kSecondsPerDay)
      ++counts.stale;
    if (f.source == FitSource::kNone) {
      ++counts.no_signal;
      continue;
    }
    ++(f.source == FitSource::kMeanMotionDerivative ? counts.from_mean_motion_derivative
                                                    : counts.from_sgp4_bstar);
    if (f.clamped < 0) ++counts.clamped_low;
    if (f.clamped > 0) ++counts.clamped_high;
    if (elements[i].bstar_per_earth_radius > 0.0)
      ratios.push_back(f.value_m2_kg /
                       (2.0 * elements[i].bstar_per_earth_radius / constants::kBstarRho0_kg_m2_per_er));
    population.drag_area_to_mass_m2_kg[i] = f.value_m2_kg;
  }
  if (!ratios.empty()) {
    auto mid = ratios.begin() + static_cast<std::ptrdiff_t>(ratios.size() / 2);
    std::nth_element(ratios.begin(), mid, ratios.end());
    counts.median_ratio_to_bstar_mapping = *mid;
  }
  return counts;
}

}  // namespace kessler
