#include "core/decay/run_atmosphere.hpp"

#include <memory>

#include "core/physics/atmosphere.hpp"
#include "core/physics/constants.hpp"
#include "core/physics/msis_grid.hpp"

namespace kessler {

DensityAt run_atmosphere_density(const ForceModelSettings& settings, const UtcEpoch& start_epoch) {
  constexpr double kRe = constants::kEarthEquatorialRadius_m;
  switch (settings.atmosphere) {
    case AtmosphereModel::kDensityTable:
      return [](const UtcEpoch&, const Eigen::Vector3d& r) {
        return DensityTable::standard().density_kg_m3(r.norm() - kRe);
      };
    case AtmosphereModel::kExponentialFit:
      return [](const UtcEpoch&, const Eigen::Vector3d& r) {
        return exponential_fit_density_kg_m3(r.norm() - kRe);
      };
    case AtmosphereModel::kNrlmsise00:
      break;
  }
  // model_input maps a position and time onto the model's inputs exactly as the grid's nodes are built.
  auto grid = std::make_shared<const MsisDensityGrid>(
      start_epoch, settings.solar_activity,
      settings.solar_activity.mode == SolarActivityMode::kConstant ? nullptr
      : settings.space_weather                                     ? settings.space_weather
                                                                   : SpaceWeather::bundled());
  return [grid, start_epoch](const UtcEpoch& when, const Eigen::Vector3d& r) {
    return nrlmsise00_density(grid->model_input(when.seconds_since(start_epoch), r)).rho_drag_kg_m3;
  };
}

std::string run_atmosphere_name(const ForceModelSettings& settings) {
  switch (settings.atmosphere) {
    case AtmosphereModel::kDensityTable:
      return "density table";
    case AtmosphereModel::kExponentialFit:
      return "exponential fit";
    case AtmosphereModel::kNrlmsise00:
      break;
  }
  switch (settings.solar_activity.mode) {
    case SolarActivityMode::kObserved:
      return "NRLMSISE-00, observed solar activity";
    case SolarActivityMode::kCycle:
      return "NRLMSISE-00, repeated solar cycle";
    case SolarActivityMode::kConstant:
      break;
  }
  return "NRLMSISE-00, constant solar activity";
}

}  // namespace kessler
