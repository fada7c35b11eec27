// Figure 8: Gabbard diagrams of the run's breakup fragments at chosen epochs.
#include <cmath>
#include <numbers>
#include <unordered_map>

#include "server/figures/figure_support.hpp"
#include "server/figures/snapshot_figures.hpp"

namespace kessler::server {

using namespace figures;

namespace {

constexpr std::size_t kMaxPointsPerPanel = 20000;

}  // namespace

nlohmann::json gabbard_figure(const std::vector<v1::Fragment>& fragments,
                              const std::vector<PopulationSnapshot>& snapshots) {
  if (fragments.empty() || snapshots.empty()) return nullptr;
  std::unordered_map<ObjectId, std::uint32_t> breakup_of;
  for (const v1::Fragment& f : fragments) breakup_of.emplace(f.id(), f.breakup_id());
  nlohmann::json values = nlohmann::json::array();
  std::uint64_t plotted = 0, left_out = 0;
  for (const PopulationSnapshot& s : snapshots) {
    std::vector<std::size_t> members;
    for (std::size_t i = 0; i < s.size(); ++i)
      if (breakup_of.count(s.id[i]) != 0 && s.eccentricity[i] < 1.0 && s.semi_major_axis_m[i] > 0.0)
        members.push_back(i);
    const std::size_t stride = (members.size() + kMaxPointsPerPanel - 1) / kMaxPointsPerPanel;
    const std::string when = time_label(s.sim_time_s);
    for (std::size_t k = 0; k < members.size(); ++k) {
      if (stride > 1 && k % stride != 0) {
        ++left_out;
        continue;
      }
      const std::size_t i = members[k];
      const double a_m = s.semi_major_axis_m[i], e = s.eccentricity[i];
      const double period_min =
          2.0 * std::numbers::pi * std::sqrt(a_m * a_m * a_m / constants::kEarthMu_m3_s2) / 60.0;
      const std::string breakup = "breakup " + std::to_string(breakup_of[s.id[i]]);
      for (const auto& [apsis, r_m] :
           {std::pair{"apogee", a_m * (1.0 + e)}, std::pair{"perigee", a_m * (1.0 - e)}})
        values.push_back({{"when", when},
                          {"breakup", breakup},
                          {"apsis", apsis},
                          {"period_min", period_min},
                          {"altitude_km", r_m / 1e3 - kEarthRadiusKm}});
      ++plotted;
    }
  }
  if (plotted == 0) return nullptr;
  nlohmann::json out =
      spec("Gabbard diagram of breakup fragments",
           std::to_string(plotted) + " fragment states plotted" +
               (left_out ? ", " + std::to_string(left_out) + " left out by even subsampling" : ""));
  out["data"] = {{"values", values}};
  out["facet"] = {
      {"column", {{"field", "when"}, {"type", "nominal"}, {"title", "epoch"}, {"sort", nullptr}}}};
  out["spec"] = {
      {"mark", {{"type", "point"}, {"size", 8}, {"filled", true}}},
      {"encoding",
       {{"x",
         {{"field", "period_min"},
          {"type", "quantitative"},
          {"scale", {{"zero", false}}},
          {"title", "period [min]"}}},
        {"y",
         {{"field", "altitude_km"}, {"type", "quantitative"}, {"title", "apogee and perigee altitude [km]"}}},
        {"shape", {{"field", "apsis"}, {"type", "nominal"}, {"title", ""}}},
        {"color", {{"field", "breakup"}, {"type", "nominal"}, {"title", ""}}}}}};
  return out;
}

}  // namespace kessler::server
