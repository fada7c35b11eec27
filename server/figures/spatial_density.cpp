// Figure 7: spatial density against altitude at the start and the end of a run, and its change.
#include <algorithm>
#include <cmath>
#include <numbers>

#include "server/figures/figure_support.hpp"
#include "server/figures/snapshot_figures.hpp"

namespace kessler::server {

using namespace figures;

nlohmann::json spatial_density_figure(const PopulationSnapshot& start, const PopulationSnapshot& end) {
  if (start.size() == 0 && end.size() == 0) return nullptr;
  constexpr double kFirstKm = 100.0, kLastKm = 2500.0;
  const DensityProfile a = spatial_density(start, kFirstKm, kLastKm),
                       b = spatial_density(end, kFirstKm, kLastKm);
  nlohmann::json values = nlohmann::json::array(), change = nlohmann::json::array();
  for (std::size_t k = 0; k < a.objects_per_km3.size(); ++k) {
    const double altitude = kFirstKm + a.shell_km * (static_cast<double>(k) + 0.5);
    values.push_back({{"altitude_km", altitude},
                      {"when", "start (" + time_label(start.sim_time_s) + ")"},
                      {"density", a.objects_per_km3[k]}});
    values.push_back({{"altitude_km", altitude},
                      {"when", "end (" + time_label(end.sim_time_s) + ")"},
                      {"density", b.objects_per_km3[k]}});
    change.push_back({{"altitude_km", altitude}, {"change", b.objects_per_km3[k] - a.objects_per_km3[k]}});
  }
  nlohmann::json out =
      spec("Spatial density against altitude",
           "objects per km^3 in 20 km shells, each orbit spread by the time it spends in each "
           "shell; " +
               std::to_string(a.objects) + " objects at the start, " + std::to_string(b.objects) +
               " at the end (unbound left out: " + std::to_string(a.unbound + b.unbound) + ")");
  const nlohmann::json x = {{"field", "altitude_km"}, {"type", "quantitative"}, {"title", "altitude [km]"}};
  out["vconcat"] = {
      {{"data", {{"values", values}}},
       {"mark", "line"},
       {"encoding",
        {{"x", x},
         {"y",
          {{"field", "density"}, {"type", "quantitative"}, {"title", "spatial density [objects / km^3]"}}},
         {"color", {{"field", "when"}, {"type", "nominal"}, {"title", ""}}}}}},
      {{"data", {{"values", change}}},
       {"mark", "bar"},
       {"encoding",
        {{"x", x},
         {"y",
          {{"field", "change"},
           {"type", "quantitative"},
           {"title", "change, end - start [objects / km^3]"}}}}}}};
  return out;
}

}  // namespace kessler::server
