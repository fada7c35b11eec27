// Figure 1: the population's distributions of mass, radius and semi-major axis by status.
#include <functional>
#include <map>

#include "server/figures/figure_support.hpp"
#include "server/figures/snapshot_figures.hpp"

namespace kessler::server {

using namespace figures;

namespace {

// One histogram panel: counts by bin and status, as rows {bin_start, bin_end, status, count}.
nlohmann::json histogram_panel(const PopulationSnapshot& s, const std::function<double(std::size_t)>& value,
                               const Bins& bins, const std::string& x_title, bool log_x) {
  std::map<std::pair<std::size_t, int>, std::uint64_t> counts;
  for (std::size_t i = 0; i < s.size(); ++i) ++counts[{bins.index(value(i)), static_cast<int>(s.status[i])}];
  nlohmann::json values = nlohmann::json::array();
  for (const auto& [key, n] : counts)
    values.push_back({{"bin_start", bins.edges[key.first]},
                      {"bin_end", bins.edges[key.first + 1]},
                      {"status", status_name(static_cast<ObjectStatus>(key.second))},
                      {"count", n}});
  nlohmann::json x = {{"field", "bin_start"}, {"type", "quantitative"}, {"title", x_title}};
  if (log_x) x["scale"] = {{"type", "log"}};
  return {{"data", {{"values", values}}},
          {"mark", {{"type", "bar"}, {"opacity", 0.8}}},
          {"encoding",
           {{"x", x},
            {"x2", {{"field", "bin_end"}}},
            {"y", {{"field", "count"}, {"type", "quantitative"}, {"stack", true}, {"title", "objects"}}},
            {"color", {{"field", "status"}, {"type", "nominal"}, {"title", "status"}}}}}};
}

}  // namespace

nlohmann::json population_distributions_figure(const PopulationSnapshot& s) {
  if (s.size() == 0) return nullptr;
  nlohmann::json out = spec("Population at " + time_label(s.sim_time_s),
                            std::to_string(s.size()) + " objects by status (step " + std::to_string(s.step) +
                                "); values outside the axes are counted in the outermost bins");
  out["hconcat"] = {
      histogram_panel(
          s, [&](std::size_t i) { return s.mass_kg[i]; }, log_bins(-3, 5, 4), "mass [kg]", true),
      histogram_panel(
          s, [&](std::size_t i) { return s.radius_m[i]; }, log_bins(-3, 2, 4), "radius [m]", true),
      histogram_panel(
          s, [&](std::size_t i) { return altitude_km(s.semi_major_axis_m[i]); }, linear_bins(0, 2500, 50),
          "semi-major axis altitude [km]", false)};
  return out;
}

}  // namespace kessler::server
